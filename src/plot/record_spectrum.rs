//! Rocking spectra of a record: in the (block size R, scale factor) plane,
//! the scales that overturn each block shaded by mode, the safe ones white,
//! below the rocking threshold grey, and the minimum overturning scale. The
//! right axis reads the scaled record's PGA in g.

use plotters::prelude::*;

use super::bands::{Band, Column, simplify, tile, tiling};
use super::render;
use super::spectrum::{
    CLASS_MODE1, CLASS_MODE2, CLASS_NO_ROCKING, CLASS_SAFE, Crossing, fill, region_legend,
    regions_of,
};
use super::style::{
    AXIS, Drawn, INK, LEGEND_WIDTH, Marker, Swatch, TICKS, X_LABEL_AREA, Y_LABEL_AREA, axis_range,
    clip_y, draw_legend, fmt_num, marker, mesh, text, tick,
};
use crate::jobs::record_spectrum::{RecordSpectrumResult, ScaleTransitionDoc, SizeDoc};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;

/// The overturning regions (lo, hi, mode) of one block size, in scale
/// factors (see [`regions_of`]).
fn regions(line: &SizeDoc, s_max: f64) -> Vec<(f64, f64, u8)> {
    let crossings =
        |list: &[ScaleTransitionDoc]| list.iter().map(Crossing::from).collect::<Vec<_>>();
    let changes: Vec<(f64, u8)> = line
        .mode_changes
        .iter()
        .map(|m| (m.scale, m.to_mode))
        .collect();
    regions_of(
        &crossings(&line.transitions),
        &changes,
        Some(&crossings(&line.principal.transitions)),
        s_max,
    )
}

/// "α = 0.25 rad, η = 0.9": the block of every size.
fn block_text(alpha: f64, eta: f64) -> String {
    format!(
        "α\u{a0}=\u{a0}{}\u{a0}rad, η\u{a0}=\u{a0}{}",
        fmt_num(alpha, 3),
        fmt_num(eta, 3)
    )
}

/// The figure of a `record_spectrum` result.
pub fn svg(result: &RecordSpectrumResult) -> Result<String, String> {
    let lines = &result.spectrum;
    if lines.is_empty() {
        return Err("the spectrum has no block sizes".into());
    }
    let spec = &result.spec;
    let s_max = spec.scale.to;
    let pga_g = result.record.peaks.pga_g;
    // Block sizes in increasing R (p decreasing).
    let mut sized: Vec<(f64, &SizeDoc)> = lines.iter().map(|l| (l.r_m, l)).collect();
    sized.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xs: Vec<f64> = sized.iter().map(|s| s.0).collect();
    let (rmin, rmax) = (xs[0], xs[xs.len() - 1]);
    let half = if rmax > rmin {
        0.5 * (rmax - rmin) / (xs.len() as f64 - 1.0).max(1.0)
    } else {
        0.25 * rmin
    };
    let (x0, x1) = if rmax > rmin {
        (rmin, rmax)
    } else {
        (rmin - 2.0 * half, rmax + 2.0 * half)
    };
    let columns: Vec<Column> = sized
        .iter()
        .map(|&(x, l)| {
            let mut bands = vec![Band {
                lo: 0.0,
                hi: l.threshold_scale.min(s_max),
                class: CLASS_NO_ROCKING,
            }];
            for (lo, hi, mode) in regions(l, s_max) {
                bands.push(Band {
                    lo,
                    hi,
                    class: if mode == 2 { CLASS_MODE2 } else { CLASS_MODE1 },
                });
            }
            let mut bands = tile(0.0, s_max, &bands, CLASS_SAFE);
            simplify(&mut bands, s_max / 1000.0, |_| false);
            Column { x, bands }
        })
        .collect();
    let shaded: Vec<_> = tiling(&columns, half)
        .pieces
        .into_iter()
        .filter(|p| p.class != CLASS_SAFE)
        .collect();
    let used = |class: usize| shaded.iter().any(|p| p.class == class);
    let minimum: Vec<(f64, f64)> = sized
        .iter()
        .filter_map(|&(x, l)| Some((x, l.min_overturn_scale?)))
        .collect();

    let mut legend = region_legend(used, "no rocking (PGA below the threshold)");
    if !minimum.is_empty() {
        legend.entry(
            Swatch::LineMark(INK, Marker::Dot),
            "minimum overturning scale (computed)",
        );
    }
    legend.note(block_text(spec.block.alpha, spec.block.eta));
    let r = &result.record;
    legend.note(format!(
        "record: {} samples, dt = {} s; PGA {} g, PGV {} m/s, PGD {} m (unscaled)",
        r.samples,
        fmt_num(r.dt_s, 4),
        fmt_num(r.peaks.pga_g, 4),
        fmt_num(r.peaks.pgv_m_s, 4),
        fmt_num(r.peaks.pgd_m, 4),
    ));
    let formulation = spec.formulation.name();
    legend.note(format!(
        "{formulation} formulation, {} block size{}; R = 3g/(4p²)",
        lines.len(),
        if lines.len() == 1 { "" } else { "s" }
    ));
    legend
        .note("shading: principal view (narrow bands omitted; the result lists every transition)");
    legend.note("right axis: the scaled record's PGA = scale × PGA");

    let title = format!("Rocking spectrum of a record: {formulation} formulation");
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        let mut builder = ChartBuilder::on(&chart_area);
        builder
            .margin(10)
            .margin_right(14)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .right_y_label_area_size(Y_LABEL_AREA);
        let chart =
            builder.build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", 0.0, s_max)?)?;
        let mut chart = chart.set_secondary_coord(x0..x1, axis_range("right", 0.0, s_max * pga_g)?);
        for piece in &shaded {
            chart.draw_series(std::iter::once(Polygon::new(
                piece.polygon.clone(),
                fill(piece.class).filled(),
            )))?;
        }
        mesh(&mut chart, "block size R (m)", "scale factor").draw()?;
        chart
            .configure_secondary_axes()
            .y_desc("scaled PGA (g)")
            .label_style(text(TICKS, INK))
            .axis_desc_style(text(AXIS, INK))
            .y_label_formatter(&|v| tick(*v))
            .draw()?;
        for piece in clip_y(&minimum, 0.0, s_max) {
            chart.draw_series(LineSeries::new(piece, INK.stroke_width(2)))?;
        }
        chart.draw_series(
            minimum
                .iter()
                .filter(|q| q.1 <= s_max)
                .map(|&q| marker(q, Marker::Dot, 5, INK)),
        )?;
        draw_legend(&side, &legend)
    })
}

#[cfg(test)]
mod tests {
    use crate::jobs::JobResult;
    use crate::jobs::record_spectrum::{
        RecordSpectrumResult, ScaleModeChangeDoc, ScalePrincipalDoc, ScaleTransitionDoc, SizeDoc,
    };
    use crate::plot::spectrum::{CLASS_MODE1, CLASS_MODE2, fill};
    use crate::plot::style::fmt_num;
    use crate::plot::tests::{hex, typed};

    fn transition(scale: f64, up: bool, mode: u8) -> ScaleTransitionDoc {
        ScaleTransitionDoc {
            scale,
            pga_g: 0.5 * scale,
            direction: if up { "up" } else { "down" }.into(),
            mode,
            impacts: u64::from(mode == 1),
            bracket: [scale - 1e-4, scale + 1e-4],
        }
    }

    /// A block size overturning in mode 2 from scale 1, in mode 1 from 1.2,
    /// with a narrow safe band 1.5–1.52 that the principal view drops.
    fn size() -> SizeDoc {
        SizeDoc {
            p: 2.0,
            r_m: 1.84,
            threshold_scale: 0.4,
            transitions: vec![
                transition(1.0, true, 2),
                transition(1.5, false, 1),
                transition(1.52, true, 1),
            ],
            mode_changes: vec![ScaleModeChangeDoc {
                scale: 1.2,
                from_mode: 2,
                to_mode: 1,
                bracket: [1.1999, 1.2001],
            }],
            min_overturn_scale: Some(1.0),
            min_overturn_pga_g: Some(0.5),
            min_overturn_mode: Some(2),
            safe_intervals: vec![[1.5, 1.52]],
            overturns_above_scale: Some(1.52),
            principal: ScalePrincipalDoc {
                transitions: vec![transition(1.0, true, 2)],
                min_overturn_scale: Some(1.0),
                min_overturn_mode: Some(2),
                safe_intervals: Vec::new(),
                overturns_above_scale: Some(1.0),
            },
        }
    }

    #[test]
    fn regions_take_the_principal_extent_and_the_full_modes() {
        let line = size();
        let crossings: Vec<crate::plot::spectrum::Crossing> =
            line.transitions.iter().map(Into::into).collect();
        assert_eq!(
            crate::plot::spectrum::intervals(&crossings, 3.0),
            vec![(1.0, 1.5, 2), (1.52, 3.0, 1)]
        );
        // The dropped gap 1.5–1.52 takes the mode below it.
        assert_eq!(
            super::regions(&line, 3.0),
            vec![(1.0, 1.2, 2), (1.2, 3.0, 1)]
        );
    }

    fn computed() -> RecordSpectrumResult {
        match typed(include_str!("../../specs/record_spectrum_one_sine.json")) {
            JobResult::RecordSpectrum(r) => *r,
            other => panic!("not a record spectrum: {:?}", other.job_kind()),
        }
    }

    #[test]
    fn the_computed_spectrum_and_its_record() {
        let doc = computed();
        assert_eq!(doc.spectrum.len(), 4);
        let svg = super::svg(&doc).expect("svg");
        let r = &doc.record;
        for needle in [
            "Rocking spectrum of a record: nonlinear formulation".to_string(),
            "block size R (m)".to_string(),
            "scaled PGA (g)".to_string(),
            format!(
                "α\u{a0}=\u{a0}{}\u{a0}rad",
                fmt_num(doc.spec.block.alpha, 3)
            ),
            format!(
                "record: {} samples, dt = {} s;",
                r.samples,
                fmt_num(r.dt_s, 4)
            ),
            "4 block".to_string(),
        ] {
            assert!(svg.contains(&needle), "missing {needle:?}");
        }
        // A block size without p: the note names α and η only.
        assert!(!svg.contains("rad/s"), "no p in the block note");
    }

    #[test]
    fn a_size_shades_its_modes() {
        let mut doc = computed();
        doc.spec.scale.to = 3.0;
        let mut other = size();
        other.r_m = 2.0;
        doc.spectrum = vec![size(), other];
        let svg = super::svg(&doc).expect("svg");
        for class in [CLASS_MODE1, CLASS_MODE2] {
            assert!(svg.contains(&hex(fill(class))), "class {class}");
        }
        assert!(svg.contains("overturns, mode 2"));
    }
}
