//! A forensic answer's mixed zones: where an observation's outcome
//! alternates finer than the scan resolves ([`crate::spectrum::verify`]),
//! with the fraction of probed levels whose outcome is the observation's,
//! and where every observation is either certainly consistent or mixed.

use super::{Intervals, LineSet, Observation};
pub use crate::jobs::mixed::MixedDoc;

/// The zones of `line` (in g) for observation `o`, within `[from,
/// line.decided_to]`: the fraction is of levels at which its block did
/// what was seen (overturned; stood; stood with its slide in the band).
pub fn observation_zones(line: &LineSet, o: &Observation, from: f64) -> Vec<MixedDoc> {
    line.mixed
        .iter()
        .filter(|z| z.to > from && z.from < line.decided_to)
        .map(|z| {
            let hits = if o.slid_m.is_some() {
                z.in_band
            } else if o.overturned {
                z.overturned
            } else {
                z.probes - z.overturned
            };
            let mut doc = MixedDoc::of(z, hits, 1.0);
            doc.from = doc.from.max(from);
            doc.to = doc.to.min(line.decided_to);
            doc
        })
        .collect()
}

/// Where every observation is certainly consistent (`consistent[i]`) or
/// mixed (`zones[i]`), and at least one is mixed: stretches with the product
/// of the fractions (the observations' outcomes alternate independently at
/// scales below the resolution), the fewest probes and the product of the
/// interval bounds. Neighbouring stretches alike are joined.
pub fn combined(consistent: &[Intervals], zones: &[Vec<MixedDoc>]) -> Vec<MixedDoc> {
    let mut cuts: Vec<f64> = consistent
        .iter()
        .flatten()
        .flat_map(|i| [i[0], i[1]])
        .chain(zones.iter().flatten().flat_map(|z| [z.from, z.to]))
        .collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut out: Vec<MixedDoc> = Vec::new();
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let mid = 0.5 * (a + b);
        let mut stretch = Some(MixedDoc {
            from: a,
            to: b,
            fraction: 1.0,
            probes: u64::MAX,
            interval_95: [1.0, 1.0],
        });
        let mut any_mixed = false;
        for (set, zs) in consistent.iter().zip(zones) {
            let Some(s) = stretch.as_mut() else { break };
            if set.iter().any(|i| i[0] <= mid && mid <= i[1]) {
                continue;
            }
            match zs.iter().find(|z| z.from <= mid && mid <= z.to) {
                Some(z) => {
                    any_mixed = true;
                    s.fraction *= z.fraction;
                    s.probes = s.probes.min(z.probes);
                    s.interval_95 = [
                        s.interval_95[0] * z.interval_95[0],
                        s.interval_95[1] * z.interval_95[1],
                    ];
                }
                None => stretch = None,
            }
        }
        let Some(s) = stretch.filter(|_| any_mixed) else {
            continue;
        };
        match out.last_mut() {
            Some(last)
                if last.to == s.from && last.fraction == s.fraction && last.probes == s.probes =>
            {
                last.to = s.to;
            }
            _ => out.push(s),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zone(from: f64, to: f64, fraction: f64, probes: u64) -> MixedDoc {
        MixedDoc {
            from,
            to,
            fraction,
            probes,
            interval_95: [fraction * 0.5, fraction.sqrt()],
        }
    }

    #[test]
    fn the_combined_answer_is_mixed_where_none_is_inconsistent_and_one_is_mixed() {
        // a: consistent on [0, 1] and [2, 3], mixed on [1, 2].
        // b: consistent on [0.5, 1.5], mixed on [1.5, 2.5].
        let consistent = vec![vec![[0.0, 1.0], [2.0, 3.0]], vec![[0.5, 1.5]]];
        let zones = vec![vec![zone(1.0, 2.0, 0.5, 40)], vec![zone(1.5, 2.5, 0.4, 20)]];
        let c = combined(&consistent, &zones);
        assert_eq!(c.len(), 3, "{c:?}");
        // [1, 1.5]: a mixed, b consistent.
        assert_eq!(
            (c[0].from, c[0].to, c[0].fraction, c[0].probes),
            (1.0, 1.5, 0.5, 40)
        );
        // [1.5, 2]: both mixed: the product, the fewest probes.
        assert_eq!((c[1].from, c[1].to, c[1].probes), (1.5, 2.0, 20));
        assert!((c[1].fraction - 0.2).abs() < 1e-15);
        // [2, 2.5]: a consistent, b mixed.
        assert_eq!((c[2].from, c[2].to, c[2].fraction), (2.0, 2.5, 0.4));
        // [0.5, 1] is certain for both: not mixed. [2.5, 3]: b inconsistent.
    }
}
