//! Sets of amplitudes as sorted, disjoint intervals: those that overturn a
//! block, those a slide observation allows, their complements and
//! intersections.

use crate::spectrum::scan::{Direction, Transition};
/// Intervals [lo, hi] of amplitude, g, sorted and disjoint.
pub type Intervals = Vec<[f64; 2]>;

/// What one line (an observation's block at one frequency, or under the
/// record) decides, g.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineSet {
    /// Amplitudes at which the block overturns.
    pub overturning: Intervals,
    /// The line decides amplitudes up to here (the range asked, or on a
    /// Coulomb floor the block's leaving the floor).
    pub decided_to: f64,
    /// On a Coulomb floor: the lowest amplitude found at which the block
    /// leaves the floor.
    pub lift_off_g: Option<f64>,
    /// For an observation with `slid_m`: the amplitudes at which the block
    /// stands with its residual slide's size in the band.
    pub slide_band: Option<Intervals>,
    /// Where the outcome alternates finer than the scan resolves, g: no
    /// amplitude inside is claimed consistent or not.
    pub mixed: Vec<crate::spectrum::verify::Mixed>,
}

impl LineSet {
    /// The amplitudes consistent with a block seen `overturned` (or
    /// standing), from `from`.
    pub fn consistent(&self, overturned: bool, from: f64) -> Intervals {
        let all = if let Some(band) = &self.slide_band {
            clip(band, from, self.decided_to)
        } else if overturned {
            self.overturning.clone()
        } else {
            complement(&self.overturning, from, self.decided_to)
        };
        crate::spectrum::verify::outside(&all, &self.mixed)
    }

    /// Where the block certainly overturns: outside the mixed zones.
    pub fn certain_overturning(&self) -> Intervals {
        crate::spectrum::verify::outside(&self.overturning, &self.mixed)
    }
}

/// Where a line with `transitions` (of a block of slenderness `alpha`) overturns, in g, within
/// `[from, to]`.
pub fn overturning_set(transitions: &[Transition], alpha: f64, from: f64, to: f64) -> Intervals {
    let mut out = Vec::new();
    let mut open: Option<f64> = None;
    for t in transitions {
        let at = t.at * alpha;
        match t.direction {
            Direction::Up => open = Some(at),
            Direction::Down => {
                if let Some(lo) = open.take() {
                    out.push([lo, at]);
                }
            }
            Direction::SlideIn | Direction::SlideOut => {}
        }
    }
    if let Some(lo) = open {
        out.push([lo, to]);
    }
    clip(&out, from, to)
}

/// Where a line's block (of slenderness `alpha`) stands with its residual
/// slide in the band, in g within `[from, to]`, from the band's edges
/// (`transitions`, in order) and whether the line's first level is inside
/// it (`inside`; the block has not moved there, nor anywhere below).
pub fn slide_band_set(
    transitions: &[Transition],
    inside: bool,
    alpha: f64,
    from: f64,
    to: f64,
) -> Intervals {
    let mut out = Vec::new();
    let mut open = inside.then_some(from);
    for t in transitions {
        let at = t.at * alpha;
        match t.direction {
            Direction::SlideIn => open = Some(at),
            Direction::SlideOut => {
                if let Some(lo) = open.take() {
                    out.push([lo, at]);
                }
            }
            _ => {}
        }
    }
    if let Some(lo) = open {
        out.push([lo, to]);
    }
    clip(&out, from, to)
}

pub(super) fn clip(set: &[[f64; 2]], from: f64, to: f64) -> Intervals {
    set.iter()
        .map(|&[a, b]| [a.max(from), b.min(to)])
        .filter(|[a, b]| b > a)
        .collect()
}

/// `[from, to]` without `set`.
pub fn complement(set: &[[f64; 2]], from: f64, to: f64) -> Intervals {
    let mut out = Vec::new();
    let mut lo = from;
    for &[a, b] in set {
        if a > lo {
            out.push([lo, a]);
        }
        lo = lo.max(b);
    }
    if to > lo {
        out.push([lo, to]);
    }
    out
}

/// The amplitudes in both sets.
pub fn intersect(x: &[[f64; 2]], y: &[[f64; 2]]) -> Intervals {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < x.len() && j < y.len() {
        let lo = x[i][0].max(y[j][0]);
        let hi = x[i][1].min(y[j][1]);
        if hi > lo {
            out.push([lo, hi]);
        }
        if x[i][1] < y[j][1] {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}
