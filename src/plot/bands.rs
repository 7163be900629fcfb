//! Regions of a plane sampled along x: at each sample (a frequency, a
//! block size) the y range (amplitudes, scale factors) is tiled by bands of
//! a class (an overturning mode, the set of observations that rule a pulse
//! out). Each sample is drawn as a cell of its own reaching half-way to its
//! neighbours and ending at the first and last samples — [`cells`], or
//! [`joined_cells`] with the cells of a class merged across their shared
//! edges — or as a bar of its own (the record spectra); nothing is
//! interpolated between samples, where nothing was computed. [`widen`]
//! keeps narrow bands visible rather than dropping them.
//!
//! The strip is tiled: no holes, no overlaps.

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

/// `bands` (disjoint) without the stretches `zones` (`[lo, hi]`), which
/// are added as bands of class `class` of their own: a region over which
/// nothing else is claimed.
pub fn over(bands: &[Band], zones: &[[f64; 2]], class: usize) -> Vec<Band> {
    let mut out: Vec<Band> = Vec::new();
    for b in bands {
        let mut lo = b.lo;
        for &[z0, z1] in zones.iter().filter(|z| z[1] > b.lo && z[0] < b.hi) {
            if z0 > lo {
                out.push(Band { hi: z0, lo, ..*b });
            }
            lo = lo.max(z1);
        }
        if b.hi > lo {
            out.push(Band { lo, ..*b });
        }
    }
    out.extend(zones.iter().map(|&[lo, hi]| Band { lo, hi, class }));
    out
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

/// The least height a band is drawn at, as a fraction of its axis: about
/// 3 px on the figures' charts (some 540 px tall), seen at the web page's
/// scale too.
pub const MIN_VISIBLE: f64 = 0.005;

/// A tiling (bands from the bottom up, meeting) whose bands of the classes
/// `keep` asks for are at least `min` tall: each narrower one widened to
/// `min` about its middle (within the tiling's range), over its neighbours.
/// Nothing is dropped: every point of a kept band lies in a band of a kept
/// class of the result, and a narrow one in a band at least `min` tall.
pub fn widen(bands: &[Band], min: f64, keep: impl Fn(usize) -> bool) -> Vec<Band> {
    let (Some(first), Some(last)) = (bands.first(), bands.last()) else {
        return Vec::new();
    };
    let (lo, hi) = (first.lo, last.hi);
    let min = min.min(hi - lo);
    let grown: Vec<Band> = bands
        .iter()
        .filter(|b| keep(b.class) && b.hi - b.lo < min)
        .map(|b| {
            let start = (0.5 * (b.lo + b.hi) - 0.5 * min).clamp(lo, hi - min);
            Band {
                lo: start,
                hi: start + min,
                class: b.class,
            }
        })
        .collect();
    let mut out = bands.to_vec();
    for b in grown {
        out = paint(&out, b);
    }
    out
}

/// `bands` (a tiling) with `b` laid over it.
fn paint(bands: &[Band], b: Band) -> Vec<Band> {
    let mut out = Vec::with_capacity(bands.len() + 2);
    for x in bands.iter().filter(|x| x.lo < b.lo) {
        push(
            &mut out,
            Band {
                hi: x.hi.min(b.lo),
                ..*x
            },
        );
    }
    push(&mut out, b);
    for x in bands.iter().filter(|x| x.hi > b.hi) {
        push(
            &mut out,
            Band {
                lo: x.lo.max(b.hi),
                ..*x
            },
        );
    }
    out
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

/// Each of `columns` (any order) as a cell of its own as in [`cells`], and
/// the cells of a class that meet across the edge of two neighbouring cells
/// joined into one polygon (a staircase, its steps on the cells' edges): no
/// edge is drawn between them, so no seam shows where a viewer scales the
/// figure. A band continues into the next cell when it meets exactly one
/// band of its class there and that band meets no other; where regions
/// split or join, their cells share their edge exactly.
pub fn joined_cells(columns: &[Column], half_width: f64) -> Vec<Piece> {
    let mut cols: Vec<&Column> = columns.iter().filter(|c| c.x.is_finite()).collect();
    cols.sort_by(|a, b| a.x.total_cmp(&b.x));
    let xs: Vec<f64> = cols.iter().map(|c| c.x).collect();
    // Each run: its class and its steps (x0, x1, lo, hi), left to right.
    let mut runs: Vec<(usize, Vec<[f64; 4]>)> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut prev: &[Band] = &[];
    let meet = |a: &Band, b: &Band| a.class == b.class && a.hi.min(b.hi) > a.lo.max(b.lo);
    for (c, (x0, x1)) in cols.iter().zip(cell_edges(&xs, half_width)) {
        let mut here = Vec::with_capacity(c.bands.len());
        for b in &c.bands {
            let step = [x0, x1, b.lo, b.hi];
            let mut met = prev.iter().enumerate().filter(|(_, a)| meet(a, b));
            let only = match (met.next(), met.next()) {
                (Some((i, a)), None) if c.bands.iter().filter(|d| meet(a, d)).count() == 1 => {
                    Some(i)
                }
                _ => None,
            };
            match only.and_then(|i| open.get(i)) {
                Some(&run) => {
                    runs[run].1.push(step);
                    here.push(run);
                }
                None => {
                    here.push(runs.len());
                    runs.push((b.class, vec![step]));
                }
            }
        }
        open = here;
        prev = &c.bands;
    }
    runs.into_iter()
        .map(|(class, steps)| {
            let mut polygon: Vec<(f64, f64)> = Vec::with_capacity(4 * steps.len());
            for s in &steps {
                polygon.extend([(s[0], s[2]), (s[1], s[2])]);
            }
            for s in steps.iter().rev() {
                polygon.extend([(s[1], s[3]), (s[0], s[3])]);
            }
            polygon.dedup();
            Piece {
                class,
                polygon: without_straight_vertices(polygon),
            }
        })
        .collect()
}

/// A closed polygon of horizontal and vertical sides without the vertices
/// inside a straight side.
fn without_straight_vertices(polygon: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let n = polygon.len();
    if n < 4 {
        return polygon;
    }
    (0..n)
        .filter(|&k| {
            let (a, p, b) = (polygon[(k + n - 1) % n], polygon[k], polygon[(k + 1) % n]);
            !((a.0 == p.0 && p.0 == b.0) || (a.1 == p.1 && p.1 == b.1))
        })
        .map(|k| polygon[k])
        .collect()
}

#[cfg(test)]
mod over_tests {
    use super::{Band, over};

    #[test]
    fn a_zone_cuts_the_bands_it_overlaps_and_is_a_band_of_its_own() {
        let b = |lo, hi, class| Band { lo, hi, class };
        let out = over(&[b(1.0, 3.0, 1), b(4.0, 5.0, 2)], &[[2.0, 4.5]], 9);
        assert_eq!(out, vec![b(1.0, 2.0, 1), b(4.5, 5.0, 2), b(2.0, 4.5, 9)]);
    }
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
    fn narrow_kept_bands_are_widened_never_dropped() {
        let bands = [
            band(0.0, 1.0, 0),
            band(1.0, 1.001, 1),
            band(1.001, 5.0, 3),
            band(5.0, 5.002, 2),
            band(5.002, 9.9995, 3),
            band(9.9995, 10.0, 1),
        ];
        let keep = |c: usize| c == 1 || c == 2;
        let out = widen(&bands, 0.1, keep);
        // Still a tiling of 0–10.
        assert_eq!(out[0].lo, 0.0);
        assert_eq!(out[out.len() - 1].hi, 10.0);
        assert!(out.windows(2).all(|w| w[0].hi == w[1].lo), "{out:?}");
        // Every kept band lies inside a band of its class at least 0.1 tall
        // (the one at the top end shifted down into the range).
        for b in bands.iter().filter(|b| keep(b.class)) {
            let holder = out
                .iter()
                .find(|o| o.class == b.class && o.lo <= b.lo && o.hi >= b.hi);
            assert!(
                holder.is_some_and(|o| o.hi - o.lo >= 0.1 - 1e-12),
                "{b:?} in {out:?}"
            );
        }
        // Bands of other classes are not widened, and wide ones untouched.
        assert_eq!(widen(&bands, 0.1, |c| c == 0), bands.to_vec());
        assert_eq!((out[0].lo, out[0].class), (0.0, 0));
        assert!((out[0].hi - 0.9505).abs() < 1e-12, "{out:?}");
    }

    #[test]
    fn joined_cells_leave_no_edge_inside_a_class() {
        let cols = [
            col(0.0, &[band(0.0, 1.0, 0), band(1.0, 5.0, 1)]),
            col(1.0, &[band(0.0, 2.0, 0), band(2.0, 5.0, 1)]),
            col(
                2.0,
                &[band(0.0, 2.0, 0), band(2.0, 3.0, 1), band(3.0, 5.0, 2)],
            ),
            // Class 1 splits in two: a new piece for each, edge to edge.
            col(
                3.0,
                &[
                    band(0.0, 2.0, 0),
                    band(2.0, 2.5, 1),
                    band(2.5, 2.6, 2),
                    band(2.6, 5.0, 1),
                ],
            ),
        ];
        let pieces = joined_cells(&cols, 0.5);
        let of =
            |class: usize| -> Vec<&Piece> { pieces.iter().filter(|p| p.class == class).collect() };
        // Class 0 is one staircase from x = 0 to 3: rising to 2 at 0.5.
        assert_eq!(of(0).len(), 1);
        assert_eq!(
            of(0)[0].polygon,
            vec![
                (0.0, 0.0),
                (3.0, 0.0),
                (3.0, 2.0),
                (0.5, 2.0),
                (0.5, 1.0),
                (0.0, 1.0)
            ]
        );
        // Class 1 runs over the first three cells, then splits in two.
        assert_eq!(of(1).len(), 3);
        assert_eq!(
            of(1)[0].polygon,
            vec![
                (0.0, 1.0),
                (0.5, 1.0),
                (0.5, 2.0),
                (2.5, 2.0),
                (2.5, 3.0),
                (1.5, 3.0),
                (1.5, 5.0),
                (0.0, 5.0)
            ]
        );
        // Class 2 does not meet itself across the last edge: two pieces.
        assert_eq!(of(2).len(), 2);
        // The pieces tile the cells: their areas add up to the whole.
        let area = |p: &Piece| {
            let n = p.polygon.len();
            0.5 * (0..n)
                .map(|k| {
                    let (a, b) = (p.polygon[k], p.polygon[(k + 1) % n]);
                    a.0 * b.1 - b.0 * a.1
                })
                .sum::<f64>()
                .abs()
        };
        let total: f64 = pieces.iter().map(area).sum();
        assert!((total - 3.0 * 5.0).abs() < 1e-12, "{total}");
    }
}
