//! Mixed zones as results give them: where the outcome alternates finer
//! than the scan resolves ([`crate::spectrum::verify`]), in the axis of the
//! field that holds them, with a fraction and its interval.

use serde::{Deserialize, Serialize};

use crate::spectrum::verify::Mixed;

/// A stretch of the axis where the outcome alternates on scales finer than
/// the resolution: neither consistent nor inconsistent with certainty.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct MixedDoc {
    /// Lowest value of the stretch, in the axis of the field that holds it.
    pub from: f64,
    /// Highest value.
    pub to: f64,
    /// The fraction of the probed levels whose outcome is the
    /// observation's (for every observation at once in a combined answer:
    /// the product of theirs); for a spectrum, the fraction at which the
    /// block overturns. A sensitivity to the scale, not a probability of
    /// the earthquake.
    pub fraction: f64,
    /// Levels probed (an even lattice over the stretch; in a combined
    /// answer, the fewest of its observations').
    pub probes: u64,
    /// 95 % interval of the fraction (Wilson score; for a combined answer,
    /// the product of the bounds).
    pub interval_95: [f64; 2],
}

impl MixedDoc {
    /// A spectrum's zone `z` on an axis `scale` times its levels: the
    /// fraction at which the block overturns.
    pub fn overturning(z: &Mixed, scale: f64) -> Self {
        Self::of(z, z.overturned, scale)
    }

    /// A zone `z` (levels × `scale` in the axis) with `hits` of its probes.
    pub fn of(z: &Mixed, hits: u64, scale: f64) -> Self {
        let (fraction, interval_95) = Mixed::fraction_of(hits, z.probes);
        MixedDoc {
            from: z.from * scale,
            to: z.to * scale,
            fraction,
            probes: z.probes,
            interval_95,
        }
    }

    /// The same stretch in another unit of the axis (`x / divisor`).
    pub fn rescaled(&self, divisor: f64) -> Self {
        MixedDoc {
            from: self.from / divisor,
            to: self.to / divisor,
            ..*self
        }
    }
}

/// Where a line's lowest overturning lies: `("band", None)` in a certain
/// band, `("mixed", zone)` in a mixed zone (on an axis `scale` times the
/// levels); `(None, None)` when it never overturns.
pub fn minimum_place(
    d: &crate::spectrum::overturning::Derived,
    scale: f64,
) -> (Option<String>, Option<MixedDoc>) {
    match (d.min_overturn, &d.min_overturn_zone) {
        (None, _) => (None, None),
        (Some(_), None) => (Some("band".into()), None),
        (Some(_), Some(z)) => (Some("mixed".into()), Some(MixedDoc::overturning(z, scale))),
    }
}
