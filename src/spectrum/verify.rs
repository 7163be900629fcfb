//! Verification of a scanned line, and its mixed zones.
//!
//! The scan and its bisection ([`super::scan`]) find where the outcome
//! changes; between two changes they claim one outcome. Where the outcome
//! alternates on scales finer than the scan step (many impacts while the
//! ground still moves, η near 1, levels near the rocking threshold: the
//! sensitivity the paper warns of), the stretches between the switches found
//! are not uniform, and that claim would be wrong. So before a stretch is
//! reported as certain, its outcome is checked inside it.
//!
//! ## The rule
//! A *piece* is a run of neighbouring simulated levels with one outcome
//! (overturned or not; with a slide band, also in the band or not), from its
//! first level `l` to its last `r`. A piece between two switches and no
//! wider than twice the tolerance (a *sliver*) cannot be verified inside:
//! it is uncertain. Every other piece is probed:
//! - narrower than the scan step `h` (a piece between switches closer than a
//!   step): at l + w/4, l + w/2 and l + 3w/4;
//! - wider: at the midpoints of the two widest gaps between simulated levels
//!   within `h` of each of its ends (where a neighbouring switch's fine
//!   structure would spill over), and of up to four gaps spread over its
//!   interior: at most 8 probes.
//!
//! A piece whose probes all agree is certain. In a wide piece, a probe that
//! disagrees is bisected against its neighbours like a scan point (a band
//! hidden between two scan points is then found exactly), and the pieces
//! this makes are probed once more by the same rule. A piece that fails
//! then, or a narrow piece that fails at once, is uncertain.
//!
//! Uncertain pieces closer than `h` to each other form one *mixed zone*,
//! with everything between them (the density of switches: a certain sliver
//! between two failures a step apart is not believed). Each zone is then
//! probed on an even lattice of n = clamp(⌈32 w/h⌉, 96, 384) levels (the
//! midpoints of n equal cells) for the fraction of levels at which the
//! block overturns (or stands in the slide band): a measure of the outcome's
//! sensitivity to the scale, not a probability of the earthquake.
//!
//! The cost: up to 3 probes per piece narrower than a step and 8 per wider
//! one, the bisection of a disagreeing probe, and the lattice of each zone.
//! A line without fine structure costs a few percent more; a chaotic one up
//! to about twice its scan.

/// Probes per narrow piece, at these fractions of its width.
const NARROW_PROBES: [f64; 3] = [0.25, 0.5, 0.75];
/// Gaps probed near each end of a wide piece.
const END_GAPS: usize = 2;
/// Gaps probed spread over a wide piece's interior.
const INTERIOR_GAPS: usize = 4;
/// Lattice points per scan step of a mixed zone's width.
const LATTICE_PER_STEP: f64 = 32.0;
/// Fewest and most lattice points of a mixed zone.
const LATTICE_MIN: usize = 96;
const LATTICE_MAX: usize = 384;

/// A stretch of levels where the outcome alternates on scales finer than the
/// scan resolves: no band or safe interval is claimed inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixed {
    /// Lowest level, as the line's axis (α g).
    pub from: f64,
    /// Highest level.
    pub to: f64,
    /// Levels probed for the fraction (an even lattice over the zone).
    pub probes: u64,
    /// Of them, where the block overturned.
    pub overturned: u64,
    /// Of them, where the block stood with its residual slide in the band.
    pub in_band: u64,
    /// The lowest level inside the zone at which the block was seen to
    /// overturn (a probe or a scan level).
    pub first_overturn: Option<f64>,
}

impl Mixed {
    /// `count` of `probes` as a fraction, with its 95 % (Wilson score)
    /// interval.
    pub fn fraction_of(count: u64, probes: u64) -> (f64, [f64; 2]) {
        if probes == 0 {
            return (0.0, [0.0, 1.0]);
        }
        let n = probes as f64;
        let p = count as f64 / n;
        let z = 1.959_963_984_540_054_f64;
        let denom = 1.0 + z * z / n;
        let centre = (p + z * z / (2.0 * n)) / denom;
        let half = z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt() / denom;
        (p, [(centre - half).max(0.0), (centre + half).min(1.0)])
    }

    /// Zones sorted by level, those closer than `join` (or overlapping)
    /// made one, their counts summed.
    pub fn merged(mut zones: Vec<Mixed>, join: f64) -> Vec<Mixed> {
        zones.sort_by(|a, b| a.from.total_cmp(&b.from));
        let mut out: Vec<Mixed> = Vec::with_capacity(zones.len());
        for z in zones {
            match out.last_mut() {
                Some(last) if z.from - last.to < join => {
                    last.to = last.to.max(z.to);
                    last.probes += z.probes;
                    last.overturned += z.overturned;
                    last.in_band += z.in_band;
                    last.first_overturn = match (last.first_overturn, z.first_overturn) {
                        (Some(a), Some(b)) => Some(a.min(b)),
                        (a, b) => a.or(b),
                    };
                }
                _ => out.push(z),
            }
        }
        out
    }

    /// The same zone on an axis `k` times this one's.
    pub fn scaled(&self, k: f64) -> Mixed {
        Mixed {
            from: self.from * k,
            to: self.to * k,
            first_overturn: self.first_overturn.map(|f| f * k),
            ..*self
        }
    }

    /// Whether `level` lies inside the zone.
    pub fn contains(&self, level: f64) -> bool {
        self.from <= level && level <= self.to
    }
}

/// The pieces of `seen` (sorted by level, each level with what it found):
/// index ranges `[i0, i1]` of neighbouring levels of one `outcome`.
pub fn pieces<T, O: PartialEq>(seen: &[(f64, T)], outcome: impl Fn(&T) -> O) -> Vec<[usize; 2]> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=seen.len() {
        if i == seen.len() || outcome(&seen[i].1) != outcome(&seen[start].1) {
            if i > start {
                out.push([start, i - 1]);
            }
            start = i;
        }
    }
    out
}

/// Where to probe a piece (its simulated levels `piece`, sorted) on a line
/// of scan step `step` and tolerance `tol` ([the rule](self)).
pub fn probe_levels<T>(piece: &[(f64, T)], step: f64, tol: f64) -> Vec<f64> {
    let (Some(first), Some(last)) = (piece.first(), piece.last()) else {
        return Vec::new();
    };
    let (l, r) = (first.0, last.0);
    let w = r - l;
    if w <= 2.0 * tol {
        return Vec::new();
    }
    if w < step {
        return NARROW_PROBES.iter().map(|f| l + f * w).collect();
    }
    let gaps: Vec<(f64, f64)> = piece
        .windows(2)
        .map(|p| (p[0].0, p[1].0))
        .filter(|(a, b)| b - a > 2.0 * tol)
        .collect();
    let widest_near = |near: &dyn Fn(&(f64, f64)) -> bool| {
        let mut g: Vec<(f64, f64)> = gaps.iter().copied().filter(|x| near(x)).collect();
        g.sort_by(|x, y| (y.1 - y.0).total_cmp(&(x.1 - x.0)));
        g.truncate(END_GAPS);
        g
    };
    let mut chosen = widest_near(&|&(a, _)| a < l + step);
    chosen.extend(widest_near(&|&(_, b)| b > r - step));
    if gaps.len() > 2 * END_GAPS {
        let n = gaps.len();
        chosen.extend((1..=INTERIOR_GAPS).map(|k| gaps[k * n / (INTERIOR_GAPS + 1)]));
    }
    let mut levels: Vec<f64> = chosen.iter().map(|(a, b)| 0.5 * (a + b)).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    levels
}

/// The even lattice of a zone `[from, to]` on a line of scan step `step`.
pub fn lattice(from: f64, to: f64, step: f64) -> Vec<f64> {
    let w = to - from;
    let n = ((LATTICE_PER_STEP * w / step).ceil() as usize).clamp(LATTICE_MIN, LATTICE_MAX);
    (0..n)
        .map(|k| from + (k as f64 + 0.5) * w / n as f64)
        .collect()
}

/// The intervals of `set` (sorted, disjoint) without the zones `mixed`
/// (sorted): what is left of each, in order.
pub fn outside(set: &[[f64; 2]], mixed: &[Mixed]) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for &[a, b] in set {
        let mut lo = a;
        for z in mixed.iter().filter(|z| z.to > a && z.from < b) {
            if z.from > lo {
                out.push([lo, z.from]);
            }
            lo = lo.max(z.to);
        }
        if b > lo {
            out.push([lo, b]);
        }
    }
    out
}

/// Uncertain pieces `[l, r]` made into zones: sorted, those closer than
/// `join` joined (with what lies between).
pub fn clusters(mut uncertain: Vec<[f64; 2]>, join: f64) -> Vec<[f64; 2]> {
    uncertain.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut out: Vec<[f64; 2]> = Vec::new();
    for [l, r] in uncertain {
        match out.last_mut() {
            Some(last) if l - last[1] < join => last[1] = last[1].max(r),
            _ => out.push([l, r]),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level's outcome: overturned or not.
    fn sig(overturned: bool) -> bool {
        overturned
    }

    #[test]
    fn pieces_are_runs_of_one_outcome() {
        let seen: Vec<(f64, bool)> = [false, false, true, true, true, false]
            .iter()
            .enumerate()
            .map(|(k, &o)| (k as f64, sig(o)))
            .collect();
        assert_eq!(pieces(&seen, |o| *o), vec![[0, 1], [2, 4], [5, 5]]);
    }

    #[test]
    fn a_narrow_piece_is_probed_at_its_quarters_and_a_sliver_not_at_all() {
        let piece = [(1.0, sig(true)), (1.004, sig(true))];
        let p = probe_levels(&piece, 0.01, 1e-4);
        assert_eq!(p.len(), 3);
        assert!((p[0] - 1.001).abs() < 1e-12 && (p[2] - 1.003).abs() < 1e-12);
        let sliver = [(1.0, sig(true)), (1.0001, sig(true))];
        assert!(probe_levels(&sliver, 0.01, 1e-4).is_empty());
    }

    #[test]
    fn a_wide_piece_is_probed_near_both_ends_and_inside_at_most_eight_times() {
        // Bisection levels crowding its left end, then a scan every 0.01.
        let mut levels = vec![1.0, 1.0001, 1.0003, 1.0006, 1.0012, 1.0025, 1.005];
        levels.extend((1..=40).map(|k| 1.0 + 0.01 * k as f64));
        let piece: Vec<(f64, bool)> = levels.iter().map(|&x| (x, sig(false))).collect();
        let p = probe_levels(&piece, 0.01, 1e-4);
        assert!(p.len() <= 8 && p.len() >= 6, "{p:?}");
        assert!(p[0] < 1.01, "a probe within a step of the left end: {p:?}");
        assert!(*p.last().unwrap() > 1.39, "and of the right end: {p:?}");
        // Every probe is strictly inside a gap, never on a simulated level.
        assert!(p.iter().all(|x| !levels.contains(x)));
    }

    #[test]
    fn uncertain_pieces_a_step_apart_form_one_zone() {
        let z = clusters(
            vec![[1.3, 1.31], [1.0, 1.001], [1.005, 1.006], [1.2, 1.201]],
            0.01,
        );
        assert_eq!(z, vec![[1.0, 1.006], [1.2, 1.201], [1.3, 1.31]]);
    }

    #[test]
    fn the_wilson_interval_holds_the_fraction_and_narrows_with_probes() {
        let (p, [lo, hi]) = Mixed::fraction_of(30, 60);
        assert_eq!(p, 0.5);
        assert!(
            lo < 0.5 && hi > 0.5 && (hi - lo - 0.246).abs() < 0.01,
            "{lo} {hi}"
        );
        let (_, [lo2, hi2]) = Mixed::fraction_of(120, 240);
        assert!(hi2 - lo2 < hi - lo);
        let (p0, [a, b]) = Mixed::fraction_of(0, 16);
        assert_eq!((p0, a), (0.0, 0.0));
        assert!(b > 0.1 && b < 0.25, "{b}");
    }

    #[test]
    fn zones_merge_their_counts() {
        let z = |from, to, n, k, first| Mixed {
            from,
            to,
            probes: n,
            overturned: k,
            in_band: 0,
            first_overturn: first,
        };
        let m = Mixed::merged(
            vec![
                z(2.0, 2.5, 10, 3, Some(2.1)),
                z(1.0, 1.999, 16, 8, Some(1.5)),
            ],
            0.01,
        );
        assert_eq!(m, vec![z(1.0, 2.5, 26, 11, Some(1.5))]);
    }
}
