//! A spectrum's table: one row per transition of each frequency (a
//! frequency without any: one row, its transition's cells empty), then a
//! row per mixed zone of the frequency.
//!
//! On a Coulomb floor the table may grow at its end (a table without
//! residual slides or the pure-rocking spectrum is as it was):
//! - with residual slides (`residual_slide`), three columns
//!   `residual_slide_m`, `peak_slide_m` (m) and `outcome` (`stands`,
//!   `overturns` or `lift_off`), and after a frequency's other rows one row
//!   per amplitude of its residual-slide line: `direction`
//!   `residual_slide`, `a_alpha_g` and `a_g` its amplitude, `omega_ratio`,
//!   `omega_p_rad_per_s` and `frequency_hz` the frequency's, the three
//!   columns the point's, the other cells empty (the three are empty on the
//!   other rows);
//! - with the pure-rocking spectrum beside (`no_sliding_beside`), a last
//!   column `floor`: `coulomb` on the rows of `spectrum`, then the rows of
//!   `no_sliding`, built the same way, with `floor` `no_sliding`.

use serde::Serialize;

use crate::jobs::mixed::MixedDoc;
use crate::kinds::spectrum::{FrequencyDoc, SlidePointDoc, SpectrumResult, TransitionDoc};
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Columns, Table, TableError};

/// The rows of every frequency of the spectrum, then of those beside it.
pub fn rows(r: &SpectrumResult, table: &mut Table) -> Result<(), TableError> {
    let tail = Tail {
        slides: r
            .spectrum
            .iter()
            .chain(&r.no_sliding)
            .any(|l| l.residual_slide.as_ref().is_some_and(|p| !p.is_empty())),
        floor: !r.no_sliding.is_empty(),
    };
    let alpha = r.spec.block.alpha;
    for line in &r.spectrum {
        line_rows(table, line, alpha, tail, "coulomb")?;
    }
    for line in &r.no_sliding {
        line_rows(table, line, alpha, tail, "no_sliding")?;
    }
    Ok(())
}

/// The columns a spectrum's table ends with, past those of [`Row`].
#[derive(Clone, Copy)]
struct Tail {
    /// [`Slide`]'s, when a line has residual-slide points.
    slides: bool,
    /// [`Floor`]'s, when the pure-rocking spectrum is beside.
    floor: bool,
}

/// The rows of one frequency of a spectrum of a block of slenderness
/// `alpha`: its transitions' rows, its mixed zones', then its residual-slide
/// points', ending with the columns of `tail` (`floor` as given).
fn line_rows(
    table: &mut Table,
    line: &FrequencyDoc,
    alpha: f64,
    tail: Tail,
    floor: &'static str,
) -> Result<(), TableError> {
    let mut row = |row: Row<'_>, slide: Slide<'_>| {
        table.row((
            row,
            Columns(tail.slides.then_some(slide)),
            Columns(tail.floor.then_some(Floor { floor: Text(floor) })),
        ))
    };
    if line.transitions.is_empty() {
        row(Row::of_line(line), Slide::default())?;
    }
    for t in &line.transitions {
        row(Row::of_transition(line, t), Slide::default())?;
    }
    for z in &line.mixed {
        row(Row::of_zone(line, z, alpha), Slide::default())?;
    }
    for p in line.residual_slide.iter().flatten() {
        row(Row::of_slide(line, p, alpha), Slide::of(p))?;
    }
    Ok(())
}

/// A row of a spectrum's table: a frequency's, with a transition, a mixed
/// zone or a residual-slide point. Amplitudes are in αg (`_alpha_g`) or g
/// (`_g`).
#[derive(Serialize)]
struct Row<'a> {
    /// The frequency's ω_p/p.
    omega_ratio: Number,
    /// The transition's amplitude (bracket midpoint), a mixed zone's lowest,
    /// or a residual-slide point's.
    a_alpha_g: Option<Number>,
    /// `up` (overturning begins as the amplitude grows) or `down` (a safe
    /// interval begins); `mixed` on a mixed zone's row, `residual_slide` on
    /// a point's.
    direction: Option<Text<&'a str>>,
    /// The transition's mode on the overturning side.
    mode: Option<u8>,
    /// Its impacts on the overturning side.
    impacts: Option<u64>,
    /// Its bracket's ends.
    bracket_lo_alpha_g: Option<Number>,
    bracket_hi_alpha_g: Option<Number>,
    /// The frequency's lowest overturning amplitude.
    min_overturn_alpha_g: Option<Number>,
    /// Eq. 21, 1 + β ω_p/p (cycloidal pulses).
    eq21_alpha_g: Option<Number>,
    /// The rocking threshold.
    threshold_alpha_g: Option<Number>,
    /// The linear one-sine mode-2 boundary (corrected eq. 47).
    closed_form_mode2_alpha_g: Option<Number>,
    /// `a_alpha_g` in g.
    a_g: Option<Number>,
    /// ω_p, rad/s.
    omega_p_rad_per_s: Number,
    /// f_p = ω_p/2π, Hz.
    frequency_hz: Number,
    /// `threshold_alpha_g` in g.
    threshold_g: Option<Number>,
    /// `min_overturn_alpha_g` in g, and in m/s².
    min_overturn_g: Option<Number>,
    min_overturn_m_per_s2: Option<Number>,
    /// Its mode.
    min_overturn_mode: Option<u8>,
    /// Every amplitude above this overturns (up to a_max).
    overturns_above_alpha_g: Option<Number>,
    /// The pulse's PGV/PGA, s, and PGD/PGA, s², at this frequency.
    pgv_over_pga_s: Option<Number>,
    pgd_over_pga_s2: Option<Number>,
    /// The same three without bands narrower than the principal width.
    principal_min_overturn_alpha_g: Option<Number>,
    principal_min_overturn_mode: Option<u8>,
    principal_overturns_above_alpha_g: Option<Number>,
    /// Where `min_overturn_alpha_g` lies: `band` or `mixed`.
    min_overturn_in: Option<Text<&'a str>>,
    /// The lowest amplitude from which overturning is certain.
    min_certain_overturn_alpha_g: Option<Number>,
    /// A mixed zone's highest amplitude.
    mixed_to: Option<Number>,
    /// The fraction of its probed amplitudes at which the block overturns.
    mixed_fraction: Option<Number>,
    /// Amplitudes probed.
    mixed_probes: Option<u64>,
    /// The fraction's 95 % interval.
    mixed_interval_95_lo: Option<Number>,
    mixed_interval_95_hi: Option<Number>,
}

impl<'a> Row<'a> {
    /// The cells of the frequency alone (ω_p/p, ω_p and f_p), the others
    /// empty.
    fn of_frequency(line: &FrequencyDoc) -> Row<'a> {
        Row {
            omega_ratio: Number(line.omega_ratio),
            a_alpha_g: None,
            direction: None,
            mode: None,
            impacts: None,
            bracket_lo_alpha_g: None,
            bracket_hi_alpha_g: None,
            min_overturn_alpha_g: None,
            eq21_alpha_g: None,
            threshold_alpha_g: None,
            closed_form_mode2_alpha_g: None,
            a_g: None,
            omega_p_rad_per_s: Number(line.omega_p),
            frequency_hz: Number(line.frequency_hz),
            threshold_g: None,
            min_overturn_g: None,
            min_overturn_m_per_s2: None,
            min_overturn_mode: None,
            overturns_above_alpha_g: None,
            pgv_over_pga_s: None,
            pgd_over_pga_s2: None,
            principal_min_overturn_alpha_g: None,
            principal_min_overturn_mode: None,
            principal_overturns_above_alpha_g: None,
            min_overturn_in: None,
            min_certain_overturn_alpha_g: None,
            mixed_to: None,
            mixed_fraction: None,
            mixed_probes: None,
            mixed_interval_95_lo: None,
            mixed_interval_95_hi: None,
        }
    }

    /// Every cell of the frequency, the transition's empty.
    fn of_line(line: &'a FrequencyDoc) -> Row<'a> {
        Row {
            min_overturn_alpha_g: line.min_overturn_alpha_g.map(Number),
            eq21_alpha_g: line.eq21_alpha_g.map(Number),
            threshold_alpha_g: Some(Number(line.threshold_alpha_g)),
            closed_form_mode2_alpha_g: line.closed_form_mode2_alpha_g.map(Number),
            threshold_g: Some(Number(line.threshold_g)),
            min_overturn_g: line.min_overturn_g.map(Number),
            min_overturn_m_per_s2: line.min_overturn_m_s2.map(Number),
            min_overturn_mode: line.min_overturn_mode,
            overturns_above_alpha_g: line.overturns_above_alpha_g.map(Number),
            pgv_over_pga_s: Some(Number(line.ground.pgv_over_pga_s)),
            pgd_over_pga_s2: Some(Number(line.ground.pgd_over_pga_s2)),
            principal_min_overturn_alpha_g: line.principal.min_overturn_alpha_g.map(Number),
            principal_min_overturn_mode: line.principal.min_overturn_mode,
            principal_overturns_above_alpha_g: line.principal.overturns_above_alpha_g.map(Number),
            min_overturn_in: line.min_overturn_in.as_deref().map(Text),
            min_certain_overturn_alpha_g: line.min_certain_overturn_alpha_g.map(Number),
            ..Row::of_frequency(line)
        }
    }

    /// Transition `t` of the frequency, with every cell of the frequency.
    fn of_transition(line: &'a FrequencyDoc, t: &'a TransitionDoc) -> Row<'a> {
        Row {
            a_alpha_g: Some(Number(t.a_alpha_g)),
            direction: Some(Text(&t.direction)),
            mode: Some(t.mode),
            impacts: Some(t.impacts),
            bracket_lo_alpha_g: Some(Number(t.bracket[0])),
            bracket_hi_alpha_g: Some(Number(t.bracket[1])),
            a_g: Some(Number(t.a_g)),
            ..Row::of_line(line)
        }
    }

    /// Mixed zone `z` of the frequency, of a block of slenderness `alpha`.
    fn of_zone(line: &FrequencyDoc, z: &MixedDoc, alpha: f64) -> Row<'a> {
        Row {
            a_alpha_g: Some(Number(z.from)),
            direction: Some(Text("mixed")),
            a_g: Some(Number(z.from * alpha)),
            mixed_to: Some(Number(z.to)),
            mixed_fraction: Some(Number(z.fraction)),
            mixed_probes: Some(z.probes),
            mixed_interval_95_lo: Some(Number(z.interval_95[0])),
            mixed_interval_95_hi: Some(Number(z.interval_95[1])),
            ..Row::of_frequency(line)
        }
    }

    /// Residual-slide point `p` of the frequency, of a block of slenderness
    /// `alpha` (its slide in [`Slide`]).
    fn of_slide(line: &FrequencyDoc, p: &SlidePointDoc, alpha: f64) -> Row<'a> {
        Row {
            a_alpha_g: Some(Number(p.a_alpha_g)),
            direction: Some(Text("residual_slide")),
            a_g: Some(Number(p.a_alpha_g * alpha)),
            ..Row::of_frequency(line)
        }
    }
}

/// The columns of a residual-slide point, empty on the other rows.
#[derive(Default, Serialize)]
struct Slide<'a> {
    /// The base's slip at the end, m.
    residual_slide_m: Option<Number>,
    /// max |slip|, m.
    peak_slide_m: Option<Number>,
    /// `stands`, `overturns` or `lift_off` (left the floor: no verdict).
    outcome: Option<Text<&'a str>>,
}

impl<'a> Slide<'a> {
    fn of(p: &'a SlidePointDoc) -> Slide<'a> {
        Slide {
            residual_slide_m: Some(Number(p.residual_slide_m)),
            peak_slide_m: Some(Number(p.peak_slide_m)),
            outcome: Some(Text(&p.outcome)),
        }
    }
}

/// Which spectrum a row is of: `coulomb` or `no_sliding`.
#[derive(Serialize)]
struct Floor {
    floor: Text<&'static str>,
}

#[cfg(test)]
mod tests {
    use serde_json::Value;

    use super::*;
    use crate::api::csv::tests::{SPECTRUM, cell, csv_of, lines};
    use crate::kinds::JobResult;
    use crate::kinds::spectrum::PulseScalesDoc;
    use crate::plot::tests::typed;

    #[test]
    fn spectrum_rows_per_transition() {
        let JobResult::Spectrum(mut r) = typed(SPECTRUM) else {
            panic!("a spectrum")
        };
        let csv = csv_of(&JobResult::Spectrum(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo_alpha_g,bracket_hi_alpha_g,min_overturn_alpha_g,eq21_alpha_g,threshold_alpha_g,closed_form_mode2_alpha_g,\
             a_g,omega_p_rad_per_s,frequency_hz,threshold_g,min_overturn_g,min_overturn_m_per_s2,min_overturn_mode,overturns_above_alpha_g,\
             pgv_over_pga_s,pgd_over_pga_s2,principal_min_overturn_alpha_g,principal_min_overturn_mode,principal_overturns_above_alpha_g,\
             min_overturn_in,min_certain_overturn_alpha_g,mixed_to,mixed_fraction,mixed_probes,mixed_interval_95_lo,mixed_interval_95_hi"
        );
        let rows: usize = r
            .spectrum
            .iter()
            .map(|f| f.transitions.len().max(1) + f.mixed.len())
            .sum();
        assert_eq!(l.len(), 1 + rows);
        let line = &r.spectrum[0];
        let t = line.transitions.first().expect("a transition below a_max");
        assert!(
            l[1].starts_with(&format!(
                "{},{},{},{},{},{},{},{},{},{},{},",
                cell(&line.omega_ratio),
                cell(&t.a_alpha_g),
                t.direction,
                t.mode,
                t.impacts,
                cell(&t.bracket[0]),
                cell(&t.bracket[1]),
                line.min_overturn_alpha_g
                    .map_or_else(String::new, |x| cell(&x)),
                line.eq21_alpha_g.map_or_else(String::new, |x| cell(&x)),
                cell(&line.threshold_alpha_g),
                line.closed_form_mode2_alpha_g
                    .map_or_else(String::new, |x| cell(&x)),
            )),
            "{}",
            l[1]
        );
        // Set values: one line with two transitions, one without any.
        let mut second = r.spectrum[0].clone();
        let (mut first, up) = set_line(&r.spectrum[0]);
        let mut down = up.clone();
        (down.a_alpha_g, down.direction, down.bracket) = (2.37, "down".into(), [2.3699, 2.3701]);
        down.a_g = 0.5925;
        first.transitions = vec![up, down];
        (second.omega_ratio, second.threshold_alpha_g) = (10.0, 1.0);
        (second.min_overturn_alpha_g, second.eq21_alpha_g) = (None, Some(2.67));
        second.closed_form_mode2_alpha_g = None;
        (second.omega_p, second.frequency_hz, second.threshold_g) = (21.4, 3.4, 0.25);
        (second.min_overturn_g, second.min_overturn_m_s2) = (None, None);
        (second.min_overturn_mode, second.overturns_above_alpha_g) = (None, None);
        second.ground = PulseScalesDoc {
            pgv_over_pga_s: 0.046,
            pgd_over_pga_s2: 0.0015,
        };
        second.principal.min_overturn_alpha_g = None;
        second.principal.min_overturn_mode = None;
        second.principal.overturns_above_alpha_g = None;
        (second.min_overturn_in, second.min_certain_overturn_alpha_g) = (None, None);
        (second.mixed, second.min_overturn_zone) = (vec![], None);
        second.transitions = vec![];
        r.spectrum = vec![first, second];
        let csv = csv_of(&JobResult::Spectrum(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,",
                "2.0,2.37,down,1,1,2.3699,2.3701,1.25,1.33,1.0,,\
                 0.5925,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,",
                "10.0,,,,,,,,2.67,1.0,,,21.4,3.4,0.25,,,,,0.046,0.0015,,,,,,,,,,",
            ]
        );
    }

    /// `line` with set values (ω_p/p = 2, overturning from 1.25 αg in mode 1
    /// up to 2.37 αg), and its first transition set to an "up" at 1.25 αg.
    fn set_line(
        line: &crate::kinds::spectrum::FrequencyDoc,
    ) -> (
        crate::kinds::spectrum::FrequencyDoc,
        crate::kinds::spectrum::TransitionDoc,
    ) {
        let mut first = line.clone();
        let mut up = first.transitions[0].clone();
        (first.omega_ratio, first.threshold_alpha_g) = (2.0, 1.0);
        (first.min_overturn_alpha_g, first.eq21_alpha_g) = (Some(1.25), Some(1.33));
        first.closed_form_mode2_alpha_g = None;
        (first.omega_p, first.frequency_hz, first.threshold_g) = (4.28, 0.68, 0.25);
        (first.min_overturn_g, first.min_overturn_m_s2) = (Some(0.3125), Some(3.07));
        (first.min_overturn_mode, first.overturns_above_alpha_g) = (Some(1), Some(2.37));
        first.ground = PulseScalesDoc {
            pgv_over_pga_s: 0.23,
            pgd_over_pga_s2: 0.037,
        };
        first.principal.min_overturn_alpha_g = Some(1.25);
        first.principal.min_overturn_mode = Some(1);
        first.principal.overturns_above_alpha_g = Some(1.25);
        (first.min_overturn_in, first.min_certain_overturn_alpha_g) =
            (Some("band".into()), Some(1.25));
        (first.mixed, first.min_overturn_zone) = (vec![], None);
        (up.a_alpha_g, up.direction, up.mode, up.impacts) = (1.25, "up".into(), 1, 1);
        (up.bracket, up.a_g) = ([1.2499, 1.2501], 0.3125);
        (first, up)
    }

    /// The header of a spectrum's table without residual slides or the
    /// pure-rocking spectrum beside: as it has always been.
    const SPECTRUM_HEADER: &str = "omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo_alpha_g,bracket_hi_alpha_g,min_overturn_alpha_g,eq21_alpha_g,threshold_alpha_g,closed_form_mode2_alpha_g,\
         a_g,omega_p_rad_per_s,frequency_hz,threshold_g,min_overturn_g,min_overturn_m_per_s2,min_overturn_mode,overturns_above_alpha_g,\
         pgv_over_pga_s,pgd_over_pga_s2,principal_min_overturn_alpha_g,principal_min_overturn_mode,principal_overturns_above_alpha_g,\
         min_overturn_in,min_certain_overturn_alpha_g,mixed_to,mixed_fraction,mixed_probes,mixed_interval_95_lo,mixed_interval_95_hi";

    #[test]
    fn spectrum_residual_slides_and_the_lines_beside_have_rows_of_their_own() {
        let JobResult::Spectrum(mut r) = typed(SPECTRUM) else {
            panic!("a spectrum")
        };
        assert_eq!(r.spec.block.alpha, 0.25);
        // One line with a transition and two residual-slide points; beside
        // it, one line without any transition.
        let mut beside = r.spectrum[0].clone();
        let (mut first, up) = set_line(&r.spectrum[0]);
        first.transitions = vec![up];
        first.residual_slide = Some(vec![
            SlidePointDoc {
                a_alpha_g: 1.0,
                residual_slide_m: 0.0,
                peak_slide_m: 0.0,
                outcome: "stands".into(),
            },
            SlidePointDoc {
                a_alpha_g: 2.0,
                residual_slide_m: -0.0123,
                peak_slide_m: 0.0456,
                outcome: "overturns".into(),
            },
        ]);
        (beside.omega_ratio, beside.threshold_alpha_g) = (10.0, 1.0);
        (beside.min_overturn_alpha_g, beside.eq21_alpha_g) = (None, Some(2.67));
        beside.closed_form_mode2_alpha_g = None;
        (beside.omega_p, beside.frequency_hz, beside.threshold_g) = (21.4, 3.4, 0.25);
        (beside.min_overturn_g, beside.min_overturn_m_s2) = (None, None);
        (beside.min_overturn_mode, beside.overturns_above_alpha_g) = (None, None);
        beside.ground = PulseScalesDoc {
            pgv_over_pga_s: 0.046,
            pgd_over_pga_s2: 0.0015,
        };
        beside.principal.min_overturn_alpha_g = None;
        beside.principal.min_overturn_mode = None;
        beside.principal.overturns_above_alpha_g = None;
        (beside.min_overturn_in, beside.min_certain_overturn_alpha_g) = (None, None);
        (beside.mixed, beside.min_overturn_zone) = (vec![], None);
        beside.transitions = vec![];
        beside.residual_slide = None;
        r.spectrum = vec![first];
        r.no_sliding = vec![beside];
        let table = |r: &SpectrumResult| csv_of(&JobResult::Spectrum(Box::new(r.clone())));
        let csv = table(&r);
        assert_eq!(
            lines(&csv),
            [
                format!("{SPECTRUM_HEADER},residual_slide_m,peak_slide_m,outcome,floor").as_str(),
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,,,,,coulomb",
                "2.0,1.0,residual_slide,,,,,,,,,0.25,4.28,0.68,,,,,,,,,,,,,,,,,,0.0,0.0,stands,coulomb",
                "2.0,2.0,residual_slide,,,,,,,,,0.5,4.28,0.68,,,,,,,,,,,,,,,,,,-0.0123,0.0456,overturns,coulomb",
                "10.0,,,,,,,,2.67,1.0,,,21.4,3.4,0.25,,,,,0.046,0.0015,,,,,,,,,,,,,,no_sliding",
            ]
        );
        // Residual slides alone: no `floor`.
        let mut alone = r.clone();
        alone.no_sliding = vec![];
        let csv = table(&alone);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            format!("{SPECTRUM_HEADER},residual_slide_m,peak_slide_m,outcome")
        );
        assert_eq!(l.len(), 4);
        assert_eq!(
            l[3],
            "2.0,2.0,residual_slide,,,,,,,,,0.5,4.28,0.68,,,,,,,,,,,,,,,,,,-0.0123,0.0456,overturns"
        );
        // The lines beside alone: `floor` right after the usual columns.
        let mut beside_only = r.clone();
        beside_only.spectrum[0].residual_slide = None;
        let csv = table(&beside_only);
        assert_eq!(
            lines(&csv),
            [
                format!("{SPECTRUM_HEADER},floor").as_str(),
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,,coulomb",
                "10.0,,,,,,,,2.67,1.0,,,21.4,3.4,0.25,,,,,0.046,0.0015,,,,,,,,,,,no_sliding",
            ]
        );
        // Neither: the table as it was.
        let mut neither = beside_only;
        neither.no_sliding = vec![];
        let csv = table(&neither);
        assert_eq!(
            lines(&csv),
            [
                SPECTRUM_HEADER,
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,",
            ]
        );
    }

    /// Each residual row of lines `floor` (of a block of α = 0.25) in a
    /// table of `header` holds its point and its frequency; nothing else.
    fn residual_rows_hold_their_point(floor: &[Value], residual: &[&Vec<&str>], header: &[&str]) {
        let at = |name: &str| header.iter().position(|h| *h == name).expect(name);
        let direction = at("direction");
        let number = |v: &Value| cell(&v.as_f64().expect("a number"));
        for (k, line) in floor.iter().enumerate() {
            let mine: Vec<&&Vec<&str>> = residual
                .iter()
                .filter(|c| c[0] == number(&line["omega_ratio"]))
                .collect();
            let line_points = line["residual_slide"].as_array().expect("asked");
            assert_eq!(mine.len(), line_points.len(), "line {k}");
            for (c, p) in mine.iter().zip(line_points) {
                let a = p["a_alpha_g"].as_f64().expect("αg");
                let text = p["outcome"].as_str().expect("outcome").to_string();
                let expected = [
                    ("omega_ratio", number(&line["omega_ratio"])),
                    ("a_alpha_g", number(&p["a_alpha_g"])),
                    ("a_g", cell(&(a * 0.25))),
                    ("omega_p_rad_per_s", number(&line["omega_p"])),
                    ("frequency_hz", number(&line["frequency_hz"])),
                    ("residual_slide_m", number(&p["residual_slide_m"])),
                    ("peak_slide_m", number(&p["peak_slide_m"])),
                    ("outcome", text),
                    ("floor", "coulomb".to_string()),
                ];
                for (name, value) in &expected {
                    assert_eq!(c[at(name)], value.as_str(), "{name} in {c:?}");
                }
                for (j, field) in c.iter().enumerate() {
                    let filled = expected.iter().any(|(n, _)| at(n) == j) || j == direction;
                    assert!(filled || field.is_empty(), "{} in {c:?}", header[j]);
                }
            }
        }
    }

    #[test]
    fn a_coulomb_spectrum_lists_its_residual_slides_and_the_pure_rocking_lines() {
        // The locomotive on μ = 0.3 on a coarse grid (as the spectrum's own
        // tests run it), with its residual slides and pure rocking beside.
        let doc = crate::plot::tests::computed(
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},
                "omega_ratio":[3,6],"a_max_alpha_g":4,"tolerance":1e-3,"scan_step_alpha_g":0.05,
                "contact":{"model":"coulomb","mu":0.3},"residual_slide":{"steps":4},"no_sliding_beside":true}"#,
        );
        let JobResult::Spectrum(r) = JobResult::from_value(doc.clone()).expect("typed") else {
            panic!("a spectrum")
        };
        let csv = csv_of(&JobResult::Spectrum(r.clone()));
        let l = lines(&csv);
        let header: Vec<&str> = l[0].split(',').collect();
        assert_eq!(
            l[0],
            format!("{SPECTRUM_HEADER},residual_slide_m,peak_slide_m,outcome,floor")
        );
        let at = |name: &str| header.iter().position(|h| *h == name).expect(name);
        let rows: Vec<Vec<&str>> = l[1..].iter().map(|r| r.split(',').collect()).collect();
        assert!(rows.iter().all(|c| c.len() == header.len()), "{csv}");
        // A row per transition (or one) of each line, a row per point of
        // its residual slide; then the lines beside, without residual slides.
        let lines_of = |key: &str| doc[key].as_array().expect("lines").clone();
        let (floor, beside) = (lines_of("spectrum"), lines_of("no_sliding"));
        assert_eq!((floor.len(), beside.len()), (2, 2));
        let count = |line: &Value, key: &str| line[key].as_array().map_or(0, Vec::len);
        let points: usize = floor.iter().map(|f| count(f, "residual_slide")).sum();
        assert_eq!(points, 2 * 4);
        let transition_rows = |lines: &[Value]| -> usize {
            lines.iter().map(|f| count(f, "transitions").max(1)).sum()
        };
        let on_floor = transition_rows(&floor) + points;
        assert_eq!(rows.len(), on_floor + transition_rows(&beside));
        let direction = at("direction");
        let residual: Vec<&Vec<&str>> = rows
            .iter()
            .filter(|c| c[direction] == "residual_slide")
            .collect();
        assert_eq!(residual.len(), points);
        assert!(beside.iter().all(|f| f.get("residual_slide").is_none()));
        // `floor`: coulomb, then no_sliding.
        let floors: Vec<&str> = rows.iter().map(|c| c[at("floor")]).collect();
        assert!(floors[..on_floor].iter().all(|f| *f == "coulomb"), "{csv}");
        assert!(
            floors[on_floor..].iter().all(|f| *f == "no_sliding"),
            "{csv}"
        );
        residual_rows_hold_their_point(&floor, &residual, &header);
        // The points are at a_max·k/4, k = 1…4, of each line in turn.
        let levels: Vec<&str> = residual.iter().map(|c| c[at("a_alpha_g")]).collect();
        assert_eq!(
            levels,
            ["1.0", "2.0", "3.0", "4.0", "1.0", "2.0", "3.0", "4.0"]
        );
        // Transition rows leave the slide columns empty.
        for c in rows.iter().filter(|c| c[direction] != "residual_slide") {
            for name in ["residual_slide_m", "peak_slide_m", "outcome"] {
                assert!(c[at(name)].is_empty(), "{name} in {c:?}");
            }
        }
        // Without them, the table of the floor's lines as it always was.
        let mut plain = *r;
        plain.no_sliding = vec![];
        for line in &mut plain.spectrum {
            line.residual_slide = None;
        }
        let csv = csv_of(&JobResult::Spectrum(Box::new(plain.clone())));
        let l = lines(&csv);
        assert_eq!(l[0], SPECTRUM_HEADER);
        assert_eq!(l.len(), 1 + transition_rows(&floor));
        assert!(l.iter().all(|r| r.split(',').count() == 31), "{csv}");
        assert!(!csv.contains("residual_slide") && !csv.contains("coulomb"));
    }
}
