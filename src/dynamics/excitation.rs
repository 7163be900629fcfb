//! Ground-acceleration pulses: the cycloidal pulses of the paper (Makris &
//! Roussos; eqs. 22 and 53), Housner's (1963) half-sine and rectangular
//! pulses, and two wavelets: Ricker's and the Mavroeidis–Papageorgiou (2003)
//! near-fault pulse ([`super::mavroeidis_papageorgiou`]).
//!
//! Every pulse is written as `ü_g(t) = a_p cos(ω t + φ)` on `0 ≤ t ≤ T` and zero
//! otherwise, with time measured from the start of the ground motion and ω the
//! carrier frequency (ω_p, or 0 for the rectangular pulse):
//! - one-sine (Type A, eq. 22): φ = −π/2, T = 2π/ω_p;
//! - one-cosine (Type B, eq. 53): φ = 0, T = 2π/ω_p;
//! - Type Cn: φ = φ_n, the root of tan φ · ((2n+1)π − 2φ) = 2, and
//!   T = ((2n+1)π − 2φ)/ω_p, so that ground velocity and displacement end at zero;
//! - half-sine (Housner): ü_g = a_p sin(ω_p t), φ = −π/2, T = π/ω_p;
//! - rectangular (Housner): ü_g = a_p, ω = 0, φ = 0, T = t_d = π/ω_p.
//!
//! So the closed-form linear solution (eqs. 23–33, written for a sinusoid)
//! holds for all of them: with ω = 0 its particular solution is the constant
//! one. The wavelets are not sinusoids: they are integrated, and their
//! threshold crossings are located between their extrema, found when the
//! pulse is built ([`Extrema`]).

use std::f64::consts::{FRAC_PI_2, PI};

use super::mavroeidis_papageorgiou::{MAX_EXTREMA, MavroeidisPapageorgiou};

/// A real parameter of a pulse family (γ, ν), finite, held by its bit
/// pattern so that a family is `Eq` and `Hash` like the integer-parametrised
/// ones: two values are the same parameter exactly when they are the same
/// number (−0 is read as +0).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Real(u64);

impl Real {
    /// `x`, unless it is not finite.
    pub fn new(x: f64) -> Option<Self> {
        x.is_finite().then(|| Real((x + 0.0).to_bits()))
    }

    /// The number.
    pub fn get(self) -> f64 {
        f64::from_bits(self.0)
    }
}

impl std::fmt::Debug for Real {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.get().fmt(f)
    }
}

/// The pulse family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PulseShape {
    /// One full sine cycle of acceleration (Type A).
    OneSine,
    /// One full cosine cycle of acceleration (Type B).
    OneCosine,
    /// Type Cn with `n ≥ 1` displacement cycles.
    Cn(u32),
    /// Half a sine cycle of acceleration (Housner 1963).
    HalfSine,
    /// Constant acceleration for t_d = π/ω_p (Housner 1963).
    Rectangular,
    /// Ricker wavelet (Vassiliou & Makris 2011): symmetric, or its derivative
    /// (antisymmetric), over 0 ≤ t ≤ 3/f_p.
    Ricker {
        /// The symmetric wavelet (true) or its normalised derivative.
        symmetric: bool,
    },
    /// Mavroeidis & Papageorgiou (2003): the ground velocity is a harmonic
    /// of phase ν under a cosine bell γ carrier cycles long, over
    /// 0 ≤ t ≤ γ/f_p, scaled so that max |ü_g| = |a_p|.
    MavroeidisPapageorgiou {
        /// γ, carrier cycles under the bell (1 < γ ≤ 20).
        gamma: Real,
        /// ν, phase of the carrier at the bell's centre, rad, in (−π, π].
        nu: Real,
    },
}

impl PulseShape {
    /// Whether ü_g is a_p cos(ω t + φ), so that the closed-form linear
    /// solution (eqs. 23–33) applies.
    pub fn is_sinusoidal(self) -> bool {
        !matches!(
            self,
            PulseShape::Ricker { .. } | PulseShape::MavroeidisPapageorgiou { .. }
        )
    }

    /// The Mavroeidis–Papageorgiou family of `gamma` and `nu` (ν taken
    /// modulo 2π, to (−π, π]); `None` unless 1 < γ ≤ 20 and ν is finite.
    pub fn mavroeidis_papageorgiou(gamma: f64, nu: f64) -> Option<Self> {
        let shape = MavroeidisPapageorgiou::new(gamma, nu)?;
        Some(PulseShape::MavroeidisPapageorgiou {
            gamma: Real::new(shape.gamma)?,
            nu: Real::new(shape.nu)?,
        })
    }
}

/// The waveform of a pulse of unit amplitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Wave {
    /// cos(ω t + φ) (the carrier and phase of the [`Pulse`]).
    Cosine,
    /// Ricker: with τ = t − t₀, the symmetric (1 − 2cτ²)e^(−cτ²), or
    /// D(τ)/max|D| with D = (−6cτ + 4c²τ³)e^(−cτ²); c = (π f_p)², t₀ = 1.5/f_p.
    Ricker {
        /// (π f_p)², 1/s².
        c: f64,
        /// Centre t₀, s.
        t0: f64,
        /// Symmetric wavelet, or its normalised derivative.
        symmetric: bool,
        /// 1, or 1/max|D| for the derivative.
        scale: f64,
    },
    /// Mavroeidis–Papageorgiou: the shape's dv/dx at x = f_p t, scaled to peak 1.
    MavroeidisPapageorgiou {
        /// f_p, Hz: x per second.
        rate: f64,
        /// γ and ν.
        shape: MavroeidisPapageorgiou,
        /// 1/max |dv/dx| over the support.
        scale: f64,
    },
}

/// The times of the extrema of a wavelet's ü_g inside its support, in
/// increasing order: found once when the pulse is built, and kept in a
/// fixed-size list so that a pulse is `Copy` and a simulation allocates
/// nothing. Between two of them ü_g is monotone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extrema {
    /// The times, s; the first `count` hold.
    times: [f64; MAX_EXTREMA],
    /// How many.
    count: usize,
}

impl Extrema {
    /// None (a sinusoid's are handled in closed form).
    pub const NONE: Extrema = Extrema {
        times: [0.0; MAX_EXTREMA],
        count: 0,
    };

    /// The first `count` of `times`, scaled by `factor`.
    fn of(times: &[f64], factor: f64) -> Extrema {
        let mut out = Extrema::NONE;
        for (slot, &t) in out.times.iter_mut().zip(times) {
            *slot = t * factor;
            out.count += 1;
        }
        out
    }

    /// The times, s.
    pub fn as_slice(&self) -> &[f64] {
        &self.times[..self.count]
    }
}

/// max |D(τ)| of the antisymmetric Ricker wavelet, at cτ*² = (3 − √6)/2.
fn ricker_derivative_peak(c: f64) -> f64 {
    let x = (3.0 - 6f64.sqrt()) / 2.0;
    let tau = (x / c).sqrt();
    ((-6.0 * c * tau + 4.0 * c * c * tau.powi(3)) * (-x).exp()).abs()
}

/// The times of the Ricker wavelet's extrema, in increasing order.
fn ricker_extrema(c: f64, t0: f64, symmetric: bool) -> Extrema {
    if symmetric {
        // ((1 − 2x)e^(−x))' = 0: τ = 0 and cτ² = 3/2.
        let r = (1.5 / c).sqrt();
        Extrema::of(&[t0 - r, t0, t0 + r], 1.0)
    } else {
        // 8x² − 24x + 6 = 0: cτ² = (3 ∓ √6)/2.
        let a = ((3.0 - 6f64.sqrt()) / 2.0 / c).sqrt();
        let b = ((3.0 + 6f64.sqrt()) / 2.0 / c).sqrt();
        Extrema::of(&[t0 - b, t0 - a, t0 + a, t0 + b], 1.0)
    }
}

impl Wave {
    /// The Ricker wavelet of centre `t0` and `c` = (π f_p)², symmetric or the
    /// derivative, at `t` (no support check).
    pub fn ricker(c: f64, t0: f64, symmetric: bool) -> Wave {
        Wave::Ricker {
            c,
            t0,
            symmetric,
            scale: if symmetric {
                1.0
            } else {
                1.0 / ricker_derivative_peak(c)
            },
        }
    }

    /// The unit waveform at `t` (no support check); the cosine needs its
    /// pulse's carrier and phase ([`Pulse::unit`]) and reads 0 here.
    #[inline]
    pub fn value(&self, t: f64) -> f64 {
        match *self {
            Wave::Cosine => 0.0,
            Wave::Ricker {
                c,
                t0,
                symmetric,
                scale,
            } => {
                let tau = t - t0;
                let x = c * tau * tau;
                if symmetric {
                    (1.0 - 2.0 * x) * (-x).exp()
                } else {
                    (-6.0 * c * tau + 4.0 * c * c * tau * tau * tau) * (-x).exp() * scale
                }
            }
            Wave::MavroeidisPapageorgiou { rate, shape, scale } => {
                scale * shape.acceleration(rate * t)
            }
        }
    }
}

/// Why a pulse cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PulseError {
    /// Amplitude must be finite and non-zero.
    #[error("pulse amplitude must be finite and non-zero (got {0})")]
    Amplitude(f64),
    /// Circular frequency must be positive and finite.
    #[error("pulse circular frequency must be positive and finite (got {0})")]
    Frequency(f64),
    /// Cn needs n ≥ 1.
    #[error("Type-Cn pulses need n >= 1 (got {0})")]
    Cycles(u32),
    /// γ of a Mavroeidis–Papageorgiou pulse outside (1, 20], or ν not finite.
    #[error(
        "Mavroeidis-Papageorgiou pulses need 1 < gamma <= 20 and a finite nu (got gamma = {0}, nu = {1})"
    )]
    Shape(f64, f64),
}

/// A ground-acceleration pulse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulse {
    /// Family.
    pub shape: PulseShape,
    /// Acceleration amplitude a_p, m/s², either sign.
    pub amplitude: f64,
    /// Circular frequency ω_p, rad/s (for the rectangular pulse, π/t_d).
    pub circular_frequency: f64,
    /// Carrier frequency ω of `a_p cos(ω t + φ)`, rad/s: ω_p, or 0 for the
    /// rectangular pulse.
    pub carrier: f64,
    /// Phase φ of `a_p cos(ω t + φ)`.
    pub phase: f64,
    /// The waveform (a cosine, or a wavelet).
    pub wave: Wave,
    /// Duration T, s.
    pub duration: f64,
    /// A wavelet's extrema of ü_g (none for a sinusoid).
    pub extrema: Extrema,
}

/// The phase of a Type-Cn pulse: the root in (0, π/2) of
/// tan φ · ((2n+1)π − 2φ) = 2 (n = 1 gives φ ≈ 0.0697π).
pub fn cn_phase(n: u32) -> f64 {
    let span = f64::from(2 * n + 1) * PI;
    let f = |phi: f64| phi.tan() * (span - 2.0 * phi) - 2.0;
    let (mut lo, mut hi) = (0.0, FRAC_PI_2 - 1e-12);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// The first stretch of time during which |ü_g| exceeds a threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exceedance {
    /// When |ü_g| first exceeds the threshold (at or after the time asked from).
    pub start: f64,
    /// When |ü_g| falls back to the threshold (or the pulse ends).
    pub end: f64,
    /// The side the ground pushes the block to: −1 (θ < 0) for ü_g > 0, +1 otherwise.
    pub side: f64,
}

impl Pulse {
    /// Builds a pulse of the given family.
    pub fn new(
        shape: PulseShape,
        amplitude: f64,
        circular_frequency: f64,
    ) -> Result<Self, PulseError> {
        if !(amplitude.is_finite() && amplitude != 0.0) {
            return Err(PulseError::Amplitude(amplitude));
        }
        if !(circular_frequency > 0.0 && circular_frequency.is_finite()) {
            return Err(PulseError::Frequency(circular_frequency));
        }
        let (phase, span) = match shape {
            PulseShape::OneSine => (-FRAC_PI_2, 2.0 * PI),
            PulseShape::OneCosine => (0.0, 2.0 * PI),
            PulseShape::Cn(n) => {
                if n == 0 {
                    return Err(PulseError::Cycles(n));
                }
                let phi = cn_phase(n);
                (phi, f64::from(2 * n + 1) * PI - 2.0 * phi)
            }
            PulseShape::HalfSine => (-FRAC_PI_2, PI),
            PulseShape::Rectangular => (0.0, PI),
            // Support 0 ≤ t ≤ 2t₀ = 3/f_p = 6π/ω_p.
            PulseShape::Ricker { .. } => (0.0, 6.0 * PI),
            // Support 0 ≤ t ≤ γ/f_p = 2πγ/ω_p.
            PulseShape::MavroeidisPapageorgiou { gamma, .. } => (0.0, 2.0 * PI * gamma.get()),
        };
        let f = circular_frequency / (2.0 * PI);
        let (wave, extrema) = match shape {
            PulseShape::Ricker { symmetric } => {
                let (c, t0) = ((PI * f).powi(2), 1.5 / f);
                (
                    Wave::ricker(c, t0, symmetric),
                    ricker_extrema(c, t0, symmetric),
                )
            }
            PulseShape::MavroeidisPapageorgiou { gamma, nu } => {
                let (gamma, nu) = (gamma.get(), nu.get());
                let shape =
                    MavroeidisPapageorgiou::new(gamma, nu).ok_or(PulseError::Shape(gamma, nu))?;
                // Located once, in x = f_p t: they set the scale and the pieces.
                let (x, n) = shape.acceleration_extrema();
                let wave = Wave::MavroeidisPapageorgiou {
                    rate: f,
                    shape,
                    scale: 1.0 / shape.peak_acceleration(&x[..n]),
                };
                (wave, Extrema::of(&x[..n], 1.0 / f))
            }
            _ => (Wave::Cosine, Extrema::NONE),
        };
        let carrier = if shape == PulseShape::Rectangular {
            0.0
        } else {
            circular_frequency
        };
        Ok(Pulse {
            shape,
            amplitude,
            circular_frequency,
            carrier,
            phase,
            wave,
            duration: span / circular_frequency,
            extrema,
        })
    }

    /// The same pulse with another amplitude.
    pub fn with_amplitude(&self, amplitude: f64) -> Self {
        Pulse { amplitude, ..*self }
    }

    /// Ground acceleration ü_g(t), m/s².
    #[inline]
    pub fn acceleration(&self, t: f64) -> f64 {
        if (0.0..=self.duration).contains(&t) {
            self.amplitude * self.unit(t)
        } else {
            0.0
        }
    }

    /// The waveform of unit amplitude at `t` (no support check).
    #[inline]
    pub fn unit(&self, t: f64) -> f64 {
        match self.wave {
            Wave::Cosine => (self.carrier * t + self.phase).cos(),
            wave => wave.value(t),
        }
    }

    /// The waveform of unit amplitude and its slope d/dt at `t` (no support
    /// check): −ω sin(ω t + φ) for the cosine; for the Ricker wavelets, with
    /// x = cτ², W′ = D = (−6cτ + 4c²τ³)e^(−x) and D′ = c(−6 + 24x − 8x²)e^(−x);
    /// for Mavroeidis–Papageorgiou, f_p times the shape's jerk.
    #[inline]
    pub fn unit_and_slope(&self, t: f64) -> (f64, f64) {
        match self.wave {
            Wave::Cosine => {
                let (s, c) = (self.carrier * t + self.phase).sin_cos();
                (c, -self.carrier * s)
            }
            Wave::Ricker {
                c,
                t0,
                symmetric,
                scale,
            } => {
                let tau = t - t0;
                let x = c * tau * tau;
                let e = (-x).exp();
                let d = (-6.0 * c * tau + 4.0 * c * c * tau * tau * tau) * e;
                if symmetric {
                    ((1.0 - 2.0 * x) * e, d)
                } else {
                    let slope = c * (-6.0 + 24.0 * x - 8.0 * x * x) * e;
                    (d * scale, slope * scale)
                }
            }
            Wave::MavroeidisPapageorgiou { rate, shape, scale } => {
                let x = rate * t;
                (scale * shape.acceleration(x), scale * rate * shape.jerk(x))
            }
        }
    }

    /// A bound on |d²/dt²| of the unit waveform over the support, where one
    /// is known in closed form: ω² for the cosine; for the Ricker wavelets,
    /// with u = √c τ and max |u|ⁿe^(−u²) = (n/2)^(n/2) e^(−n/2), the triangle
    /// inequality on W″ = c(−6 + 24u² − 8u⁴)e^(−u²) and on
    /// D″ = c^(3/2)(60u − 80u³ + 16u⁵)e^(−u²). `None` for
    /// Mavroeidis–Papageorgiou.
    pub fn unit_curvature_bound(&self) -> Option<f64> {
        // max |u|ⁿ e^(−u²).
        let peak = |n: f64| (0.5 * n).powf(0.5 * n) * (-0.5 * n).exp();
        match self.wave {
            Wave::Cosine => Some(self.carrier * self.carrier),
            Wave::Ricker {
                c,
                symmetric,
                scale,
                ..
            } => Some(if symmetric {
                c * (6.0 + 24.0 * peak(2.0) + 8.0 * peak(4.0))
            } else {
                scale * c * c.sqrt() * (60.0 * peak(1.0) + 80.0 * peak(3.0) + 16.0 * peak(5.0))
            }),
            Wave::MavroeidisPapageorgiou { .. } => None,
        }
    }

    /// Phase χ = ω t + φ at time t.
    #[inline]
    pub fn phase_at(&self, t: f64) -> f64 {
        self.carrier * t + self.phase
    }

    /// Ground velocity (m/s) and displacement (m) at `t` of the motion from
    /// rest at t = 0, in closed form: the sinusoid's integrals; the
    /// symmetric Ricker W = (1 − 2cτ²)e^(−cτ²) integrates to V = τe^(−cτ²),
    /// and V to U = −e^(−cτ²)/(2c) (the antisymmetric one is W′); the
    /// Mavroeidis–Papageorgiou velocity is the pulse's definition. After the
    /// pulse the ground keeps its final velocity.
    pub fn ground_motion(&self, t: f64) -> (f64, f64) {
        if t <= 0.0 {
            return (0.0, 0.0);
        }
        if t > self.duration {
            let (v, u) = self.ground_motion(self.duration);
            return (v, u + v * (t - self.duration));
        }
        let a = self.amplitude;
        match self.wave {
            Wave::Cosine => {
                let (w, phi) = (self.carrier, self.phase);
                if w == 0.0 {
                    return (a * t, 0.5 * a * t * t);
                }
                (
                    (a / w) * ((w * t + phi).sin() - phi.sin()),
                    (a / (w * w)) * (phi.cos() - (w * t + phi).cos()) - (a / w) * t * phi.sin(),
                )
            }
            Wave::Ricker {
                c,
                t0,
                symmetric,
                scale,
            } => {
                let w = |tau: f64| (1.0 - 2.0 * c * tau * tau) * (-c * tau * tau).exp();
                let v = |tau: f64| tau * (-c * tau * tau).exp();
                let u = |tau: f64| -(-c * tau * tau).exp() / (2.0 * c);
                let (tau, ts) = (t - t0, -t0);
                if symmetric {
                    (
                        a * (v(tau) - v(ts)),
                        a * (u(tau) - u(ts) - v(ts) * (tau - ts)),
                    )
                } else {
                    let a = a * scale;
                    (
                        a * (w(tau) - w(ts)),
                        a * (v(tau) - v(ts) - w(ts) * (tau - ts)),
                    )
                }
            }
            Wave::MavroeidisPapageorgiou { rate, shape, scale } => {
                // ü_g(t) = a_p scale v′(f_p t) is the derivative of V v(f_p t)
                // for V = a_p scale/f_p; and ∫ V v(f_p t) dt = (V/f_p) ∫ v dx.
                let big_v = a * scale / rate;
                let x = rate * t;
                (
                    big_v * shape.velocity(x),
                    big_v / rate * shape.displacement(x),
                )
            }
        }
    }

    /// (PGV, PGD) of a Ricker wavelet: the ends, and every zero of ü_g (for
    /// v) and of v (for u) bracketed on a fine grid and located by Brent's
    /// method.
    fn wavelet_peaks(&self) -> (f64, f64) {
        let n = 4000;
        let dt = self.duration / n as f64;
        let acc = |t: f64| self.amplitude * self.unit(t);
        let vel = |t: f64| self.ground_motion(t).0;
        let (mut pgv, mut pgd) = (0.0f64, 0.0f64);
        for k in 0..n {
            let (ta, tb) = (k as f64 * dt, (k + 1) as f64 * dt);
            let (va, vb) = (self.ground_motion(ta), self.ground_motion(tb));
            pgv = pgv.max(va.0.abs()).max(vb.0.abs());
            pgd = pgd.max(va.1.abs()).max(vb.1.abs());
            let (aa, ab) = (acc(ta), acc(tb));
            if aa * ab < 0.0 {
                let t = crate::dynamics::events::brent(acc, ta, tb, aa, ab, 0.0);
                pgv = pgv.max(vel(t).abs());
            }
            if va.0 * vb.0 < 0.0 {
                let t = crate::dynamics::events::brent(vel, ta, tb, va.0, vb.0, 0.0);
                pgd = pgd.max(self.ground_motion(t).1.abs());
            }
        }
        (pgv, pgd)
    }

    /// Peak ground velocity |v|, m/s, of the motion from rest.
    pub fn peak_velocity(&self) -> f64 {
        match self.wave {
            Wave::Cosine => {}
            Wave::Ricker { .. } => return self.wavelet_peaks().0,
            Wave::MavroeidisPapageorgiou { rate, shape, scale } => {
                return (self.amplitude * scale / rate).abs() * shape.peak_velocity();
            }
        }
        let (a, w, phi, t) = (self.amplitude, self.carrier, self.phase, self.duration);
        if w == 0.0 {
            return a.abs() * t;
        }
        // v(t) = (a/ω)(sin(ωt + φ) − sin φ): extreme at the ends or where cos(ωt + φ) = 0.
        let v = |t: f64| (a / w) * ((w * t + phi).sin() - phi.sin());
        let mut best = v(t).abs();
        let mut k = ((phi - FRAC_PI_2) / PI).ceil();
        while k * PI + FRAC_PI_2 <= w * t + phi {
            let tk = (k * PI + FRAC_PI_2 - phi) / w;
            if tk >= 0.0 {
                best = best.max(v(tk).abs());
            }
            k += 1.0;
        }
        best
    }

    /// Peak ground displacement |u|, m, of the motion from rest (the
    /// displacement keeps growing after the pulse when it ends with velocity;
    /// this is the largest over the pulse).
    pub fn peak_displacement(&self) -> f64 {
        match self.wave {
            Wave::Cosine => {}
            Wave::Ricker { .. } => return self.wavelet_peaks().1,
            Wave::MavroeidisPapageorgiou { rate, shape, scale } => {
                return (self.amplitude * scale / (rate * rate)).abs() * shape.peak_displacement();
            }
        }
        let (a, w, phi, t_end) = (self.amplitude, self.carrier, self.phase, self.duration);
        if w == 0.0 {
            return 0.5 * a.abs() * t_end * t_end;
        }
        // u(t) = (a/ω²)(cos φ − cos(ωt + φ)) − (a/ω) t sin φ; extreme at the
        // ends or where v = 0, i.e. sin(ωt + φ) = sin φ.
        let u =
            |t: f64| (a / (w * w)) * (phi.cos() - (w * t + phi).cos()) - (a / w) * t * phi.sin();
        let mut best = u(t_end).abs();
        let chi_end = w * t_end + phi;
        // sin χ = sin φ at χ = φ + 2kπ and χ = π − φ + 2kπ.
        let mut k = 0.0;
        while phi + 2.0 * k * PI <= chi_end || PI - phi + 2.0 * k * PI <= chi_end {
            for chi in [phi + 2.0 * k * PI, PI - phi + 2.0 * k * PI] {
                if chi > phi && chi <= chi_end {
                    best = best.max(u((chi - phi) / w).abs());
                }
            }
            k += 1.0;
        }
        best
    }

    /// The first exceedance of |ü_g| > `threshold` at or after `from`, located in
    /// closed form on the sinusoid. `None` if the pulse never exceeds it again.
    pub fn next_exceedance(&self, from: f64, threshold: f64) -> Option<Exceedance> {
        let amp = self.amplitude.abs();
        if amp <= threshold || threshold.is_nan() || from >= self.duration {
            return None;
        }
        let from = from.max(0.0);
        if self.wave != Wave::Cosine {
            return self.exceedance_on_monotone_pieces(from, threshold);
        }
        let w = self.carrier;
        if w == 0.0 {
            // Constant acceleration: one window, the rest of the pulse.
            return Some(Exceedance {
                start: from,
                end: self.duration,
                side: -self.amplitude.signum(),
            });
        }
        // |cos χ| > c  ⟺  χ lies within β = acos(c) of a multiple of π.
        let beta = (threshold / amp).acos();
        let chi0 = self.phase_at(from);
        let m = (chi0 / PI).floor();
        let offset = chi0 - m * PI;
        // Inside window m, unless rounding put `from` at or past its end (as
        // it may when the block comes back to rest exactly there): then the
        // next window is the one to wait for.
        let inside = offset < beta && ((m * PI + beta) - self.phase) / w > from;
        let (chi_start, k) = if inside {
            (chi0, m)
        } else if offset < beta {
            ((m + 1.0) * PI - beta, m + 1.0)
        } else if offset > PI - beta {
            (chi0, m + 1.0)
        } else {
            ((m + 1.0) * PI - beta, m + 1.0)
        };
        let start = if chi_start == chi0 {
            from
        } else {
            (chi_start - self.phase) / w
        };
        if start >= self.duration {
            return None;
        }
        let end = (((k * PI + beta) - self.phase) / w).min(self.duration);
        // Sign of ü_g in this window: cos(kπ) = (−1)^k.
        let cos_sign = if (k.rem_euclid(2.0)) == 0.0 {
            1.0
        } else {
            -1.0
        };
        let accel_sign = cos_sign * self.amplitude.signum();
        Some(Exceedance {
            start,
            end,
            side: -accel_sign,
        })
    }

    /// The first exceedance of a wavelet, searched on the pieces between its
    /// extrema, where ü_g is monotone: a crossing of ±threshold is bracketed
    /// there and located by Brent's method to rounding. Never an empty window:
    /// one that rounding closes where it opens (asked from the end of the
    /// previous one) is passed over for the next.
    fn exceedance_on_monotone_pieces(&self, from: f64, threshold: f64) -> Option<Exceedance> {
        let mut from = from;
        for _ in 0..8 {
            let (start, end, sign) = self.window_from(from, threshold)?;
            if end > start {
                return Some(Exceedance {
                    start,
                    end,
                    side: -sign,
                });
            }
            // A few ulps on, |ü_g| is below the threshold again.
            from = end + 4.0 * f64::EPSILON * end.abs().max(1.0);
        }
        None
    }

    /// (start, end, sign of ü_g) of the first stretch at or after `from` where
    /// |ü_g| > `threshold`, on a wavelet; the end may equal the start.
    fn window_from(&self, from: f64, threshold: f64) -> Option<(f64, f64, f64)> {
        if from >= self.duration {
            return None;
        }
        // Piece boundaries after `from`: the extrema inside, then the end.
        let extrema = self.extrema.as_slice();
        let inside = &extrema[extrema.partition_point(|&t| t <= from)..];
        let inside = &inside[..inside.partition_point(|&t| t < self.duration)];
        let last = [self.duration];
        let cuts = inside.iter().chain(&last).copied();
        let a = |t: f64| self.amplitude * self.unit(t);
        let mut start = None;
        let mut first_piece = 0;
        if a(from).abs() > threshold {
            start = Some(from);
        } else {
            let mut ta = from;
            for (k, tb) in cuts.clone().enumerate() {
                let at_end = a(tb);
                if at_end.abs() > threshold {
                    let level = at_end.signum() * threshold;
                    let f = |t: f64| a(t) - level;
                    let (fa, fb) = (f(ta), f(tb));
                    let t = if fa * fb < 0.0 {
                        crate::dynamics::events::brent(f, ta, tb, fa, fb, 0.0)
                    } else {
                        ta
                    };
                    start = Some(t.max(from));
                    first_piece = k;
                    break;
                }
                ta = tb;
            }
        }
        let start = start?;
        let sign = a(start).signum();
        // Where |ü_g| falls back to the threshold: ü_g = sign·threshold.
        let mut ta = start;
        for tb in cuts.skip(first_piece) {
            if tb <= start {
                continue;
            }
            let f = |t: f64| sign * a(t) - threshold;
            let (fa, fb) = (f(ta), f(tb));
            if fa > 0.0 && fb <= 0.0 {
                let end = crate::dynamics::events::brent(f, ta, tb, fa, fb, 0.0);
                return Some((start, end, sign));
            }
            ta = tb;
        }
        Some((start, self.duration, sign))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cn_phase_for_one_cycle_is_about_0_0697_pi() {
        let phi = cn_phase(1);
        assert!((phi / PI - 0.0697).abs() < 5e-4, "phi/pi = {}", phi / PI);
        assert!((phi.tan() * (3.0 * PI - 2.0 * phi) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn cn_pulse_ends_with_zero_ground_velocity_and_displacement() {
        for n in 1..4 {
            let p = Pulse::new(PulseShape::Cn(n), 1.0, 2.0).expect("valid");
            let (w, phi, t) = (p.circular_frequency, p.phase, p.duration);
            // v(T) = (a/ω)(sin(ωT+φ) − sin φ); x(T) = ∫v.
            let v_end = ((w * t + phi).sin() - phi.sin()) / w;
            let x_end = (-(w * t + phi).cos() + phi.cos()) / (w * w) - phi.sin() * t / w;
            assert!(v_end.abs() < 1e-12, "n = {n}: v = {v_end}");
            assert!(x_end.abs() < 1e-12, "n = {n}: x = {x_end}");
        }
    }

    #[test]
    fn one_sine_exceedance_starts_at_the_paper_phase() {
        let p = Pulse::new(PulseShape::OneSine, 2.0, 3.0).expect("valid");
        let e = p.next_exceedance(0.0, 1.0).expect("exceeds");
        // sin(ω t) = 1/2 → ω t = π/6 (the paper's ψ).
        assert!((e.start * 3.0 - PI / 6.0).abs() < 1e-14);
        assert!((e.end * 3.0 - 5.0 * PI / 6.0).abs() < 1e-14);
        assert_eq!(e.side, -1.0);
        let e2 = p.next_exceedance(e.end + 1e-9, 1.0).expect("second lobe");
        assert!((e2.start * 3.0 - 7.0 * PI / 6.0).abs() < 1e-14);
        assert_eq!(e2.side, 1.0);
        assert!(p.next_exceedance(e2.end + 1e-9, 1.0).is_none());
        assert!(p.next_exceedance(0.0, 2.0).is_none());
    }

    #[test]
    fn one_cosine_exceeds_from_the_start_and_negative_amplitude_mirrors() {
        let p = Pulse::new(PulseShape::OneCosine, -2.0, 1.0).expect("valid");
        let e = p.next_exceedance(0.0, 1.0).expect("exceeds");
        assert_eq!(e.start, 0.0);
        assert!((e.end - PI / 3.0).abs() < 1e-14);
        assert_eq!(e.side, 1.0);
    }

    /// The same for the Ricker wavelets, whose windows are found between
    /// their extrema: from each window's end, the next, never an empty one,
    /// and the opposite lobes of the antisymmetric wavelet each found.
    #[test]
    fn wavelet_windows_follow_each_other_never_empty() {
        for symmetric in [true, false] {
            let p = Pulse::new(PulseShape::Ricker { symmetric }, 1.0, 7.3).expect("valid");
            for threshold in [0.1, 0.4, 0.999_999, 1.0 - 1e-12] {
                let mut from = 0.0;
                let mut sides = Vec::new();
                while let Some(e) = p.next_exceedance(from, threshold) {
                    assert!(e.end > e.start, "{symmetric}, c = {threshold}: {e:?}");
                    assert!(e.start >= from);
                    let mid = 0.5 * (e.start + e.end);
                    assert!(p.acceleration(mid).abs() > threshold);
                    from = e.end;
                    sides.push(e.side);
                    assert!(sides.len() <= 5, "windows repeat");
                }
                // The lobes in order (ü_g > 0 pushes to side −1): the
                // symmetric wavelet's side lobes reach 2e^(−3/2) = 0.446 of
                // its crest, the derivative's outer lobes 0.272 of its peaks.
                let expected: &[f64] = match (symmetric, threshold) {
                    (true, t) if t < 0.446 => &[1.0, -1.0, 1.0],
                    (true, t) if t < 0.9999 => &[-1.0],
                    (false, t) if t < 0.272 => &[1.0, -1.0, 1.0, -1.0],
                    (false, t) if t < 0.9999 => &[-1.0, 1.0],
                    _ => &sides,
                };
                assert_eq!(sides, expected, "symmetric {symmetric}, c = {threshold}");
            }
        }
    }

    #[test]
    fn from_the_end_of_a_window_the_next_window_is_found_never_an_empty_one() {
        // A threshold the pulse barely exceeds: windows are a few ulps of phase
        // wide, and their computed ends may round to either side.
        for n in 1..4 {
            let p = Pulse::new(PulseShape::Cn(n), 1.0, 22.1).expect("valid");
            for threshold in [0.5, 0.999_999, 1.0 - 1e-12] {
                let mut from = 0.0;
                let mut windows = 0;
                while let Some(e) = p.next_exceedance(from, threshold) {
                    assert!(e.end > e.start, "n = {n}, c = {threshold}: {e:?}");
                    assert!(e.start >= from);
                    from = e.end;
                    windows += 1;
                    assert!(windows <= 2 * n as usize + 4, "n = {n}: windows repeat");
                }
            }
        }
    }
}
