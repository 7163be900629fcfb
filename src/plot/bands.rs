//! Regions of a plane sampled along x: at each sample (a frequency) the y
//! range (amplitudes) is tiled by bands of a class (an overturning mode, the
//! set of observations that rule a pulse out). Two ways to draw them:
//!
//! - [`tiling`] (spectra): between two samples whose bands come in the same
//!   order of classes every boundary is interpolated linearly, so boundaries
//!   read as the piecewise-linear curves of the paper's figures. A band
//!   present at one sample only is given a zero-width partner at the other
//!   (where its neighbours meet, or inside the band that surrounds it), so
//!   it tapers to a point between the samples; when no such pairing exists
//!   each sample's bands reach half-way, as steps.
//! - [`cells`] (forensic maps): each sample a cell of its own reaching
//!   half-way to its neighbours and ending at the first and last samples;
//!   nothing is interpolated.
//!
//! Either way the strip is tiled: no holes, no overlaps.

/// One band of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Class (what the band is).
    pub class: usize,
}

/// The bands of one sample, tiling the y range from the bottom up.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Where the sample is.
    pub x: f64,
    /// Its bands.
    pub bands: Vec<Band>,
}

/// A filled piece of a region.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Class of the region.
    pub class: usize,
    /// Vertices.
    pub polygon: Vec<(f64, f64)>,
}

/// A boundary segment between regions of two classes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// Its ends.
    pub segment: [(f64, f64); 2],
    /// The class on one side (below, or left).
    pub a: usize,
    /// The class on the other side (above, or right).
    pub b: usize,
}

/// What a set of columns draws as.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tiling {
    /// Filled pieces.
    pub pieces: Vec<Piece>,
    /// Every boundary between regions of different classes (the ends of the
    /// y range excluded).
    pub edges: Vec<Edge>,
}

/// `bands` (disjoint, any order) cut to `[lo, hi]`, the gaps filled with
/// `background`, neighbours of one class joined.
pub fn tile(lo: f64, hi: f64, bands: &[Band], background: usize) -> Vec<Band> {
    let mut sorted: Vec<Band> = bands
        .iter()
        .map(|b| Band {
            lo: b.lo.max(lo),
            hi: b.hi.min(hi),
            class: b.class,
        })
        .filter(|b| b.hi > b.lo)
        .collect();
    sorted.sort_by(|a, b| a.lo.total_cmp(&b.lo));
    let mut out: Vec<Band> = Vec::new();
    let mut y = lo;
    for b in sorted {
        if b.hi <= y {
            continue;
        }
        if b.lo > y {
            push(
                &mut out,
                Band {
                    lo: y,
                    hi: b.lo,
                    class: background,
                },
            );
        }
        push(
            &mut out,
            Band {
                lo: b.lo.max(y),
                ..b
            },
        );
        y = b.hi;
    }
    if hi > y {
        push(
            &mut out,
            Band {
                lo: y,
                hi,
                class: background,
            },
        );
    }
    out
}

fn push(out: &mut Vec<Band>, b: Band) {
    match out.last_mut() {
        Some(last) if last.class == b.class => last.hi = b.hi,
        _ => out.push(b),
    }
}

/// Removes bands of a tiling narrower than `width` (under a pixel, they only
/// break the continuity of their neighbours), except those `keep` asks for:
/// a removed band goes to its neighbours.
pub fn simplify(bands: &mut Vec<Band>, width: f64, keep: impl Fn(usize) -> bool) {
    loop {
        let narrowest = bands
            .iter()
            .enumerate()
            .filter(|(_, b)| b.hi - b.lo < width && !keep(b.class))
            .min_by(|a, b| (a.1.hi - a.1.lo).total_cmp(&(b.1.hi - b.1.lo)))
            .map(|(k, _)| k);
        let Some(k) = narrowest else { break };
        if bands.len() == 1 {
            break;
        }
        let removed = bands.remove(k);
        if k > 0 && k < bands.len() && bands[k - 1].class == bands[k].class {
            bands[k - 1].hi = bands[k].hi;
            bands.remove(k);
        } else if k > 0 {
            bands[k - 1].hi = removed.hi;
        } else {
            bands[0].lo = removed.lo;
        }
    }
}

fn classes(bands: &[Band]) -> Vec<usize> {
    bands.iter().map(|b| b.class).collect()
}

/// Inserts into `to` a zero-width band matching `from[k]`, the first band
/// whose class differs, if the result lines the two up further: at the
/// boundary where `to`'s neighbours meet, or splitting the band of `to`
/// that surrounds it. The point it tapers to must lie within `reach` of the
/// band, or the taper would be a long shear rather than an ending.
fn insert_partner(from: &[Band], to: &mut Vec<Band>, k: usize, reach: f64) -> bool {
    let c = from[k].class;
    let near = |y: f64| y >= from[k].lo - reach && y <= from[k].hi + reach;
    // At a boundary: what follows in `from` is what follows in `to`.
    let follows = match (from.get(k + 1), to.get(k)) {
        (Some(a), Some(b)) => a.class == b.class,
        (None, None) => true,
        _ => false,
    };
    if follows {
        let y = if k == 0 {
            to.first().map_or(from[k].lo, |b| b.lo)
        } else {
            to[k - 1].hi
        };
        if near(y) {
            to.insert(
                k,
                Band {
                    lo: y,
                    hi: y,
                    class: c,
                },
            );
            return true;
        }
    }
    // Inside: `from` has d, c, d where `to` has d.
    if k >= 1
        && from
            .get(k + 1)
            .is_some_and(|b| b.class == from[k - 1].class)
        && to[k - 1].class == from[k - 1].class
    {
        let d = to[k - 1];
        let y = (0.5 * (from[k].lo + from[k].hi)).clamp(d.lo, d.hi);
        if near(y) {
            to[k - 1].hi = y;
            to.insert(
                k,
                Band {
                    lo: y,
                    hi: y,
                    class: c,
                },
            );
            to.insert(
                k + 1,
                Band {
                    lo: y,
                    hi: d.hi,
                    class: d.class,
                },
            );
            return true;
        }
    }
    false
}

/// Whether each band of `l` plausibly continues as its partner in `r`: they
/// overlap, or lie within twice the wider one's width or half `reach` of
/// each other (a narrow band leaping far is another band, not this one
/// moved); a band tapering to a point must end within `reach` of it.
fn plausible(l: &[Band], r: &[Band], reach: f64) -> bool {
    l.iter().zip(r).all(|(a, b)| {
        let (wa, wb) = (a.hi - a.lo, b.hi - b.lo);
        let gap = (a.lo - b.hi).max(b.lo - a.hi);
        if wa <= 0.0 || wb <= 0.0 {
            gap <= reach
        } else {
            gap <= (2.0 * wa.max(wb)).max(0.5 * reach)
        }
    })
}

/// A fraction of the y range of two columns: how far a band may taper.
fn reach_of(l: &[Band], r: &[Band]) -> f64 {
    let lo = l
        .iter()
        .chain(r)
        .map(|b| b.lo)
        .fold(f64::INFINITY, f64::min);
    let hi = l
        .iter()
        .chain(r)
        .map(|b| b.hi)
        .fold(f64::NEG_INFINITY, f64::max);
    0.08 * (hi - lo)
}

/// `l` and `r` refined with zero-width bands until their classes come in the
/// same order, if that can be done.
fn align(l: &[Band], r: &[Band]) -> Option<(Vec<Band>, Vec<Band>)> {
    let (mut l, mut r) = (l.to_vec(), r.to_vec());
    // More than a band or two appearing or vanishing is not a continuation:
    // steps say so more honestly than shears.
    let limit = l.len().max(r.len()) + 2;
    let lo = l
        .iter()
        .chain(&r)
        .map(|b| b.lo)
        .fold(f64::INFINITY, f64::min);
    let hi = l
        .iter()
        .chain(&r)
        .map(|b| b.hi)
        .fold(f64::NEG_INFINITY, f64::max);
    let reach = 0.08 * (hi - lo);
    loop {
        if l.len().max(r.len()) > limit {
            return None;
        }
        let k = l
            .iter()
            .zip(&r)
            .position(|(a, b)| a.class != b.class)
            .unwrap_or(l.len().min(r.len()));
        if k == l.len() && k == r.len() {
            return Some((l, r));
        }
        let done = (k < l.len() && insert_partner(&l, &mut r, k, reach))
            || (k < r.len() && insert_partner(&r, &mut l, k, reach));
        if !done {
            return None;
        }
    }
}

fn class_at(c: &Column, y: f64) -> Option<usize> {
    c.bands
        .iter()
        .find(|b| y >= b.lo && y <= b.hi)
        .map(|b| b.class)
}

fn steps(c: &Column, x0: f64, x1: f64, out: &mut Tiling) {
    for b in &c.bands {
        out.pieces.push(Piece {
            class: b.class,
            polygon: vec![(x0, b.lo), (x1, b.lo), (x1, b.hi), (x0, b.hi)],
        });
    }
    for w in c.bands.windows(2) {
        out.edges.push(Edge {
            segment: [(x0, w[1].lo), (x1, w[1].lo)],
            a: w[0].class,
            b: w[1].class,
        });
    }
}

/// The pieces and boundaries of `columns` (any order). A single sample is
/// drawn `half_width` to either side.
pub fn tiling(columns: &[Column], half_width: f64) -> Tiling {
    let mut cols: Vec<&Column> = columns.iter().filter(|c| c.x.is_finite()).collect();
    cols.sort_by(|a, b| a.x.total_cmp(&b.x));
    let mut out = Tiling::default();
    if let [only] = cols.as_slice() {
        steps(only, only.x - half_width, only.x + half_width, &mut out);
        return out;
    }
    for pair in cols.windows(2) {
        let (l, r) = (pair[0], pair[1]);
        let aligned = if classes(&l.bands) == classes(&r.bands) {
            Some((l.bands.clone(), r.bands.clone()))
        } else {
            align(&l.bands, &r.bands)
        }
        .filter(|(a, b)| plausible(a, b, reach_of(a, b)));
        if let Some((lb, rb)) = aligned {
            for (a, b) in lb.iter().zip(&rb) {
                if a.hi <= a.lo && b.hi <= b.lo {
                    continue;
                }
                out.pieces.push(Piece {
                    class: a.class,
                    polygon: vec![(l.x, a.lo), (r.x, b.lo), (r.x, b.hi), (l.x, a.hi)],
                });
            }
            for (a, b) in lb.windows(2).zip(rb.windows(2)) {
                out.edges.push(Edge {
                    segment: [(l.x, a[1].lo), (r.x, b[1].lo)],
                    a: a[0].class,
                    b: a[1].class,
                });
            }
            continue;
        }
        let mid = 0.5 * (l.x + r.x);
        steps(l, l.x, mid, &mut out);
        steps(r, mid, r.x, &mut out);
        step_edges(l, r, mid, &mut out);
    }
    out
}

/// Where the classes of `l` and `r` differ across a step at `mid`: vertical
/// boundaries there.
fn step_edges(l: &Column, r: &Column, mid: f64, out: &mut Tiling) {
    let mut cuts: Vec<f64> = l
        .bands
        .iter()
        .chain(&r.bands)
        .flat_map(|b| [b.lo, b.hi])
        .collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut open: Option<Edge> = None;
    for w in cuts.windows(2) {
        let y = 0.5 * (w[0] + w[1]);
        let (a, b) = (class_at(l, y), class_at(r, y));
        let here = match (a, b) {
            (Some(a), Some(b)) if a != b => Some((a, b)),
            _ => None,
        };
        match (&mut open, here) {
            (Some(e), Some((a, b))) if e.a == a && e.b == b => e.segment[1].1 = w[1],
            (_, here) => {
                out.edges.extend(open.take());
                open = here.map(|(a, b)| Edge {
                    segment: [(mid, w[0]), (mid, w[1])],
                    a,
                    b,
                });
            }
        }
    }
    out.edges.extend(open);
}

/// The x extent of the cell of each of `xs` (ascending): half-way to each
/// neighbour, and no further than the first and last (a lone sample
/// reaches `half_width` either side).
pub fn cell_edges(xs: &[f64], half_width: f64) -> Vec<(f64, f64)> {
    match xs {
        [] => Vec::new(),
        [only] => vec![(only - half_width, only + half_width)],
        _ => (0..xs.len())
            .map(|k| {
                let lo = if k == 0 {
                    xs[0]
                } else {
                    0.5 * (xs[k - 1] + xs[k])
                };
                let hi = if k + 1 == xs.len() {
                    xs[k]
                } else {
                    0.5 * (xs[k] + xs[k + 1])
                };
                (lo, hi)
            })
            .collect(),
    }
}

/// Each of `columns` (any order) as a cell of its own, no interpolation
/// between samples: the extents of [`cell_edges`], the boundaries inside
/// each cell and, where the classes differ across the edge of two cells,
/// along that edge.
pub fn cells(columns: &[Column], half_width: f64) -> Tiling {
    let mut cols: Vec<&Column> = columns.iter().filter(|c| c.x.is_finite()).collect();
    cols.sort_by(|a, b| a.x.total_cmp(&b.x));
    let xs: Vec<f64> = cols.iter().map(|c| c.x).collect();
    let mut out = Tiling::default();
    for (c, (x0, x1)) in cols.iter().zip(cell_edges(&xs, half_width)) {
        steps(c, x0, x1, &mut out);
    }
    for pair in cols.windows(2) {
        step_edges(pair[0], pair[1], 0.5 * (pair[0].x + pair[1].x), &mut out);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(lo: f64, hi: f64, class: usize) -> Band {
        Band { lo, hi, class }
    }

    fn col(x: f64, bands: &[Band]) -> Column {
        Column {
            x,
            bands: bands.to_vec(),
        }
    }

    type Segment = ([(f64, f64); 2], usize, usize);

    fn segments(t: &Tiling) -> Vec<Segment> {
        t.edges.iter().map(|e| (e.segment, e.a, e.b)).collect()
    }

    #[test]
    fn same_order_of_classes_interpolates_every_boundary() {
        let cols = [
            col(
                0.0,
                &[band(0.0, 1.0, 0), band(1.0, 2.0, 1), band(2.0, 9.0, 2)],
            ),
            col(
                1.0,
                &[band(0.0, 1.5, 0), band(1.5, 2.5, 1), band(2.5, 9.0, 2)],
            ),
        ];
        let t = tiling(&cols, 0.1);
        assert_eq!(t.pieces.len(), 3);
        assert_eq!(
            t.pieces[1].polygon,
            vec![(0.0, 1.0), (1.0, 1.5), (1.0, 2.5), (0.0, 2.0)]
        );
        assert_eq!(
            segments(&t),
            vec![
                ([(0.0, 1.0), (1.0, 1.5)], 0, 1),
                ([(0.0, 2.0), (1.0, 2.5)], 1, 2)
            ]
        );
    }

    #[test]
    fn a_band_ending_between_samples_tapers_to_a_point() {
        // A bay (class 1) inside class 3 that is gone at the next sample.
        let l = [
            band(0.0, 1.0, 0),
            band(1.0, 4.0, 3),
            band(4.0, 6.0, 1),
            band(6.0, 8.0, 3),
            band(8.0, 9.0, 2),
        ];
        let r = [band(0.0, 1.0, 0), band(1.0, 8.5, 3), band(8.5, 9.0, 2)];
        let t = tiling(&[col(0.0, &l), col(1.0, &r)], 0.1);
        let bay = t.pieces.iter().find(|p| p.class == 1).expect("bay");
        assert_eq!(
            bay.polygon,
            vec![(0.0, 4.0), (1.0, 5.0), (1.0, 5.0), (0.0, 6.0)]
        );
        assert_eq!(t.pieces.len(), 5);
        // A band opening at a boundary.
        let (a, b) = align(
            &[band(0.0, 1.0, 1), band(1.0, 9.0, 2)],
            &[band(0.0, 1.0, 1), band(1.0, 1.5, 3), band(1.5, 9.0, 2)],
        )
        .expect("aligned");
        assert_eq!(a[1], band(1.0, 1.0, 3));
        assert_eq!(classes(&a), classes(&b));
        // A band at the top end vanishing.
        let (a, _) = align(
            &[band(0.0, 9.0, 3)],
            &[band(0.0, 8.0, 3), band(8.0, 9.0, 2)],
        )
        .expect("top");
        assert_eq!(a[1], band(9.0, 9.0, 2));
    }

    #[test]
    fn a_change_of_order_gives_steps_half_way() {
        let cols = [
            col(
                0.0,
                &[band(0.0, 1.0, 0), band(1.0, 2.0, 1), band(2.0, 5.0, 2)],
            ),
            col(
                2.0,
                &[band(0.0, 1.0, 2), band(1.0, 2.0, 1), band(2.0, 5.0, 0)],
            ),
        ];
        let t = tiling(&cols, 0.1);
        assert_eq!(t.pieces.len(), 6);
        assert_eq!(t.pieces[0].polygon[1], (1.0, 0.0));
        // Each half's two boundaries, and the vertical steps where the
        // classes differ across the middle.
        let s = segments(&t);
        assert_eq!(s.len(), 6);
        assert_eq!(s[4], ([(1.0, 0.0), (1.0, 1.0)], 0, 2));
        assert_eq!(s[5], ([(1.0, 2.0), (1.0, 5.0)], 2, 0));
    }

    #[test]
    fn a_narrow_band_leaping_far_is_not_joined() {
        let cols = [
            col(
                0.0,
                &[band(0.0, 5.0, 1), band(5.0, 5.1, 0), band(5.1, 9.0, 1)],
            ),
            col(
                1.0,
                &[band(0.0, 2.0, 1), band(2.0, 2.1, 0), band(2.1, 9.0, 1)],
            ),
        ];
        let t = tiling(&cols, 0.1);
        assert_eq!(t.pieces.len(), 6);
        assert!(t.pieces.iter().all(|p| p.polygon[0].1 == p.polygon[1].1));
    }

    #[test]
    fn tiles_fill_gaps_and_narrow_bands_go() {
        let t = tile(
            0.0,
            10.0,
            &[band(2.0, 3.0, 1), band(3.0, 4.0, 1), band(6.0, 12.0, 2)],
            9,
        );
        assert_eq!(
            t,
            vec![
                band(0.0, 2.0, 9),
                band(2.0, 4.0, 1),
                band(4.0, 6.0, 9),
                band(6.0, 10.0, 2)
            ]
        );
        let mut b = vec![
            band(0.0, 1.0, 0),
            band(1.0, 1.001, 1),
            band(1.001, 2.0, 0),
            band(2.0, 2.0005, 2),
        ];
        simplify(&mut b, 0.01, |c| c == 2);
        assert_eq!(b, vec![band(0.0, 2.0, 0), band(2.0, 2.0005, 2)]);
    }

    #[test]
    fn cells_reach_half_way_and_stop_at_the_first_and_last_samples() {
        assert_eq!(
            cell_edges(&[0.25, 0.5, 1.0], 0.1),
            vec![(0.25, 0.375), (0.375, 0.75), (0.75, 1.0)]
        );
        let cols = [
            col(0.0, &[band(0.0, 1.0, 0), band(1.0, 5.0, 1)]),
            col(1.0, &[band(0.0, 2.0, 0), band(2.0, 5.0, 1)]),
            col(2.0, &[band(0.0, 5.0, 1)]),
        ];
        let t = cells(&cols, 0.5);
        // Rectangles only: each piece is level at its top and bottom.
        assert!(
            t.pieces
                .iter()
                .all(|p| p.polygon[0].1 == p.polygon[1].1 && p.polygon[2].1 == p.polygon[3].1)
        );
        let right = t
            .pieces
            .iter()
            .flat_map(|p| p.polygon.iter().map(|q| q.0))
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(right, 2.0);
        // Class 0 of the middle cell ends at its edge (1.5): no taper to 2.
        let zero_right = t
            .pieces
            .iter()
            .filter(|p| p.class == 0)
            .flat_map(|p| p.polygon.iter().map(|q| q.0))
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(zero_right, 1.5);
        // Vertical boundaries where the classes differ across an edge.
        assert!(
            segments(&t).contains(&([(0.5, 1.0), (0.5, 2.0)], 1, 0)),
            "{:?}",
            segments(&t)
        );
        assert!(segments(&t).contains(&([(1.5, 0.0), (1.5, 2.0)], 0, 1)));
    }

    #[test]
    fn one_sample_is_a_bar() {
        let t = tiling(&[col(1.0, &[band(0.0, 1.0, 0), band(1.0, 2.0, 1)])], 0.5);
        assert_eq!(t.pieces[0].polygon[0], (0.5, 0.0));
        assert_eq!(t.edges[0].segment, [(0.5, 1.0), (1.5, 1.0)]);
    }
}
