//! A time history's table: its series when it has one; else its impacts;
//! else a one-row summary.

use serde::Serialize;

use crate::kinds::time_history::{ImpactDoc, SeriesDoc, TimeHistoryResult};
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Columns, Table, TableError};

/// The series when there is one; else the impacts; else a one-row summary.
pub fn rows(r: &TimeHistoryResult, table: &mut Table) -> Result<(), TableError> {
    if let Some(s) = &r.series
        && series(s, r.spec.block.g, table)?
    {
        return Ok(());
    }
    let impacts = r.impacts.as_deref().unwrap_or_default();
    if !impacts.is_empty() {
        for (k, i) in impacts.iter().enumerate() {
            table.row(ImpactRow::of(k, i))?;
        }
        return Ok(());
    }
    summary(r, table)
}

/// A row of a time history's series: its samples at one step. A column the
/// series does not have (`None`: no samples) is left out of the table; a
/// cell past the end of its column is empty. The vertical ground
/// acceleration (under a vertical ground motion only) comes after the
/// columns every series has, as columns added later do.
///
/// Cells `C` are the samples of a typed result, or those read from a stored
/// document ([`crate::api::csv::stream`]).
#[derive(Serialize)]
pub struct SeriesRow<'a, C> {
    /// Time, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_s: Option<C>,
    /// The block's rotation θ, rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theta_rad: Option<C>,
    /// Its rate θ̇, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theta_dot_rad_per_s: Option<C>,
    /// The horizontal ground acceleration, m/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_acceleration_m_per_s2: Option<C>,
    /// The friction demand f_x/f_z (empty where it is not defined).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fx_over_fz: Option<C>,
    /// The vertical ground acceleration, m/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_vertical_acceleration_m_per_s2: Option<C>,
    /// The same in g (with the block's g).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ug_v_g: Option<C>,
    /// On a Coulomb floor: the base's slip, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slide_m: Option<C>,
    /// On a Coulomb floor: how the block moves (the result's word, as it
    /// is).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode: Option<Option<&'a str>>,
}

/// The series' rows, when it has samples (whether it had).
fn series(s: &SeriesDoc, g: f64, table: &mut Table) -> Result<bool, TableError> {
    let vertical = s
        .ground_vertical_acceleration
        .as_deref()
        .unwrap_or_default();
    let in_g: Vec<f64> = vertical.iter().map(|a| a / g).collect();
    let fx = s.fx_over_fz.as_deref().unwrap_or_default();
    let slide = s.slide_m.as_deref().unwrap_or_default();
    let modes = s.mode.as_deref().unwrap_or_default();
    let lengths = [
        s.t.len(),
        s.theta.len(),
        s.theta_dot.len(),
        s.ground_acceleration.len(),
        fx.len(),
        vertical.len(),
        slide.len(),
        modes.len(),
    ];
    let rows = lengths.into_iter().max().unwrap_or(0);
    // Sample `k` of a column, when the series has the column.
    fn sample<'c, T, C>(
        column: &'c [T],
        k: usize,
        cell: impl Fn(&'c T) -> Option<C>,
    ) -> Option<Option<C>> {
        (!column.is_empty()).then(|| column.get(k).and_then(cell))
    }
    let number = |x: &f64| Some(Number(*x));
    for k in 0..rows {
        table.row(SeriesRow {
            t_s: sample(&s.t, k, number),
            theta_rad: sample(&s.theta, k, number),
            theta_dot_rad_per_s: sample(&s.theta_dot, k, number),
            ground_acceleration_m_per_s2: sample(&s.ground_acceleration, k, number),
            fx_over_fz: sample(fx, k, |x| x.map(Number)),
            ground_vertical_acceleration_m_per_s2: sample(vertical, k, number),
            ug_v_g: sample(&in_g, k, number),
            slide_m: sample(slide, k, number),
            mode: sample(modes, k, |m| Some(m.as_str())),
        })?;
    }
    Ok(rows > 0)
}

/// An impact of a history without a series.
#[derive(Serialize)]
struct ImpactRow {
    /// Its number, from 1.
    impact: usize,
    /// When, s.
    t_s: Number,
    /// θ̇ before it, rad/s.
    theta_dot_before_rad_per_s: Number,
    /// θ̇ after it, rad/s.
    theta_dot_after_rad_per_s: Number,
}

impl ImpactRow {
    /// Impact `i`, the `k`-th (from 0).
    fn of(k: usize, i: &ImpactDoc) -> ImpactRow {
        ImpactRow {
            impact: k + 1,
            t_s: Number(i.t),
            theta_dot_before_rad_per_s: Number(i.theta_dot_before),
            theta_dot_after_rad_per_s: Number(i.theta_dot_after),
        }
    }
}

/// The summary of a history without series or impacts: the result's
/// figures, then (under a vertical ground motion) its peak, then (on a
/// Coulomb floor) how the block moved on it.
fn summary(r: &TimeHistoryResult, table: &mut Table) -> Result<(), TableError> {
    let peaks = &r.ground_peaks;
    let vertical =
        (peaks.pga_v_m_s2.is_some() || peaks.pga_v_g.is_some()).then_some(VerticalPeak {
            pga_v_m_per_s2: peaks.pga_v_m_s2.map(Number),
            pga_v_g: peaks.pga_v_g.map(Number),
        });
    let coulomb = r.contact_model.is_some().then(|| Coulomb {
        contact_model: r.contact_model.as_deref().map(Text),
        answered_by: r.answered_by.as_deref().map(Text),
        initial_mode: r.initial_mode.as_deref().map(Text),
        peak_slide_m: r.peak_slide_m.map(Number),
        residual_slide_m: r.residual_slide_m.map(Number),
        time_sliding_s: r.time_sliding_s.map(Number),
    });
    table.row((Summary::of(r), Columns(vertical), Columns(coulomb)))
}

/// The figures of a history, as the result names them.
#[derive(Serialize)]
struct Summary {
    /// Whether the block rocked.
    rocked: bool,
    /// Whether it overturned.
    overturned: bool,
    /// The overturning mode: 1 (after an impact) or 2 (without).
    mode: Option<u8>,
    /// Impacts.
    impact_count: u64,
    /// When rocking started, s.
    rocking_start_s: Option<Number>,
    /// When the block overturned, s.
    overturn_time_s: Option<Number>,
    /// When it came to rest, s.
    rest_time_s: Option<Number>,
    /// The end of the history, s.
    end_time_s: Number,
    /// max |θ|/α.
    peak_theta_over_alpha: Number,
    /// max |f_x/f_z|: the least μ for pure rocking.
    peak_friction_demand: Option<Number>,
    /// f_x/f_z when rocking starts.
    initiation_friction_demand: Option<Number>,
    /// Whether f_z reached 0.
    lift_off: Option<bool>,
    /// When it first did, s.
    lift_off_time_s: Option<Number>,
    /// Times the block started to rock.
    rocking_starts: u32,
    /// Impacts of chattering tails, summed in closed form (counted in
    /// `impact_count`).
    chatter_impacts_summed: u64,
    /// When the outcome became certain, s.
    decided_at_s: Number,
    /// When the friction demand peaked, s.
    peak_friction_demand_time_s: Option<Number>,
    /// The friction demand was followed up to this time only (the block
    /// was then bound to overturn), s.
    friction_demand_followed_until_s: Option<Number>,
    /// The ground's peak acceleration, m/s².
    pga_m_per_s2: Number,
    /// The same in g.
    pga_g: Number,
    /// Its peak velocity, m/s.
    pgv_m_per_s: Number,
    /// Its peak displacement, m.
    pgd_m: Number,
    /// PGV/PGA, s.
    pgv_over_pga_s: Number,
    /// The side the block overturned to: +1 about the corner at +x, −1
    /// the other.
    overturn_direction: Option<Number>,
}

impl Summary {
    fn of(r: &TimeHistoryResult) -> Summary {
        let peaks = &r.ground_peaks;
        Summary {
            rocked: r.rocked,
            overturned: r.overturned,
            mode: r.mode,
            impact_count: r.impact_count,
            rocking_start_s: r.rocking_start.map(Number),
            overturn_time_s: r.overturn_time.map(Number),
            rest_time_s: r.rest_time.map(Number),
            end_time_s: Number(r.end_time),
            peak_theta_over_alpha: Number(r.peak_theta_over_alpha),
            peak_friction_demand: r.peak_friction_demand.map(Number),
            initiation_friction_demand: r.initiation_friction_demand.map(Number),
            lift_off: r.lift_off,
            lift_off_time_s: r.lift_off_time.map(Number),
            rocking_starts: r.rocking_starts,
            chatter_impacts_summed: r.chatter_impacts_summed,
            decided_at_s: Number(r.decided_at),
            peak_friction_demand_time_s: r.peak_friction_demand_time.map(Number),
            friction_demand_followed_until_s: r.friction_demand_followed_until.map(Number),
            pga_m_per_s2: Number(peaks.pga_m_s2),
            pga_g: Number(peaks.pga_g),
            pgv_m_per_s: Number(peaks.pgv_m_s),
            pgd_m: Number(peaks.pgd_m),
            pgv_over_pga_s: Number(peaks.pgv_over_pga_s),
            overturn_direction: r.overturn_direction.map(Number),
        }
    }
}

/// Under a vertical ground motion: its peak.
#[derive(Serialize)]
struct VerticalPeak {
    /// m/s².
    pga_v_m_per_s2: Option<Number>,
    /// g.
    pga_v_g: Option<Number>,
}

/// On a Coulomb floor: how the block moved on it.
#[derive(Serialize)]
struct Coulomb<'a> {
    /// The contact model (`coulomb`).
    contact_model: Option<Text<&'a str>>,
    /// What answered: pure rocking's history, or the modes'.
    answered_by: Option<Text<&'a str>>,
    /// The mode the block first left rest in.
    initial_mode: Option<Text<&'a str>>,
    /// max |slip|, m.
    peak_slide_m: Option<Number>,
    /// The slip at the end, m.
    residual_slide_m: Option<Number>,
    /// Time spent sliding, s.
    time_sliding_s: Option<Number>,
}

#[cfg(test)]
mod tests {
    use crate::api::csv::stream::SeriesRows;
    use crate::api::csv::tests::{TIME_HISTORY, cell, lines, th_table, time_history_result};
    use crate::kinds::JobResult;
    use crate::kinds::time_history::{ImpactDoc, SeriesDoc};
    use crate::plot::tests::typed;

    #[test]
    fn time_history_series_with_units() {
        let r = time_history_result();
        let s = r.series.clone().expect("a series");
        let ratio = s.fx_over_fz.clone().expect("reactions are followed");
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2,fx_over_fz"
        );
        assert_eq!(l.len(), s.t.len() + 1);
        assert!(s.t.len() > 2);
        let k = 2;
        assert_eq!(
            l[k + 1],
            [
                cell(&s.t[k]),
                cell(&s.theta[k]),
                cell(&s.theta_dot[k]),
                cell(&s.ground_acceleration[k]),
                ratio[k].map_or_else(String::new, |x| cell(&x)),
            ]
            .join(",")
        );
        // Numbers as JSON writes them.
        let mut r = r;
        r.series = Some(SeriesDoc {
            t: vec![0.0, 0.1, 0.2],
            theta: vec![0.0, -0.01, -0.02],
            theta_dot: vec![0.0, -0.1, -0.2],
            ground_acceleration: vec![0.0, 1.0, 2.0],
            ground_vertical_acceleration: None,
            fx_over_fz: Some(vec![Some(0.0), Some(0.25), None]),
            slide_m: None,
            mode: None,
        });
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(l.len(), 4);
        assert_eq!(l[2], "0.1,-0.01,-0.1,1.0,0.25");
        assert_eq!(l[3], "0.2,-0.02,-0.2,2.0,");
        // Without reactions the ratio column is left out.
        if let Some(s) = &mut r.series {
            s.fx_over_fz = None;
        }
        let csv = th_table(&r);
        assert!(
            csv.starts_with("t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2\n")
        );
    }

    #[test]
    fn a_vertical_ground_motion_adds_its_column_at_the_end() {
        let spec = TIME_HISTORY.replace(r#""outputs":"#, r#""vertical":{"ratio":-0.6},"outputs":"#);
        let r = match typed(&spec) {
            JobResult::TimeHistory(r) => *r,
            other => panic!("not a time history: {:?}", other.job_kind()),
        };
        let s = r.series.clone().expect("a series");
        let vertical = s
            .ground_vertical_acceleration
            .clone()
            .expect("the vertical acceleration");
        assert_eq!(vertical.len(), s.t.len());
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2,fx_over_fz,ground_vertical_acceleration_m_per_s2,ug_v_g"
        );
        assert_eq!(l.len(), s.t.len() + 1);
        let g = r.spec.block.g;
        for k in 0..s.t.len() {
            let mut fields = l[k + 1].rsplit(',');
            let in_g = fields.next().expect("a field");
            let m_s2 = fields.next().expect("a field");
            assert_eq!(m_s2, cell(&vertical[k]), "row {k}");
            assert_eq!(in_g, cell(&(vertical[k] / g)), "row {k}");
        }
        // ü_v = −0.6 ü_g while the pulse lasts: some rows hold both.
        assert!(vertical.iter().any(|v| *v != 0.0));
        // Not streamed from the stored document: its column in g is worked out.
        let text = serde_json::to_string(&r).expect("json");
        assert!(SeriesRows::of(&text).is_none());
        // Without a vertical motion there is no such column.
        assert!(!th_table(&time_history_result()).contains("vertical"));
    }

    #[test]
    fn time_history_without_series_gives_its_impacts() {
        let mut r = time_history_result();
        r.series = None;
        let impacts = r.impacts.clone().expect("impacts are listed");
        assert!(!impacts.is_empty(), "the block rocks and impacts");
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "impact,t_s,theta_dot_before_rad_per_s,theta_dot_after_rad_per_s"
        );
        assert_eq!(l.len(), impacts.len() + 1);
        let i = impacts[0];
        assert_eq!(
            l[1],
            format!(
                "1,{},{},{}",
                cell(&i.t),
                cell(&i.theta_dot_before),
                cell(&i.theta_dot_after)
            )
        );
        r.impacts = Some(vec![ImpactDoc {
            t: 1.5,
            theta_dot_before: 0.5,
            theta_dot_after: -0.45,
        }]);
        assert_eq!(
            lines(&th_table(&r)),
            vec![
                "impact,t_s,theta_dot_before_rad_per_s,theta_dot_after_rad_per_s",
                "1,1.5,0.5,-0.45"
            ]
        );
    }

    #[test]
    fn time_history_without_series_or_impacts_gives_a_summary() {
        let mut r = time_history_result();
        // An empty series and no impacts: the summary.
        r.series = Some(SeriesDoc {
            t: vec![],
            theta: vec![],
            theta_dot: vec![],
            ground_acceleration: vec![],
            ground_vertical_acceleration: None,
            fx_over_fz: None,
            slide_m: None,
            mode: None,
        });
        r.impacts = None;
        r.rocked = false;
        r.overturned = false;
        r.overturn_direction = None;
        r.mode = None;
        r.impact_count = 0;
        r.rocking_start = None;
        r.overturn_time = None;
        r.rest_time = None;
        r.end_time = 1.0;
        r.peak_theta_over_alpha = 0.0;
        r.peak_friction_demand = None;
        r.initiation_friction_demand = None;
        r.lift_off = None;
        r.lift_off_time = None;
        (r.rocking_starts, r.chatter_impacts_summed, r.decided_at) = (0, 0, 1.0);
        r.peak_friction_demand_time = None;
        r.friction_demand_followed_until = None;
        r.ground_peaks.pga_m_s2 = 2.5 * 0.25 * 9.81;
        r.ground_peaks.pga_g = 0.625;
        r.ground_peaks.pgv_m_s = 0.43;
        r.ground_peaks.pgd_m = 0.07;
        r.ground_peaks.pgv_over_pga_s = 0.07;
        assert_eq!(
            lines(&th_table(&r)),
            vec![
                "rocked,overturned,mode,impact_count,rocking_start_s,overturn_time_s,rest_time_s,end_time_s,peak_theta_over_alpha,peak_friction_demand,initiation_friction_demand,lift_off,lift_off_time_s,\
                 rocking_starts,chatter_impacts_summed,decided_at_s,peak_friction_demand_time_s,friction_demand_followed_until_s,pga_m_per_s2,pga_g,pgv_m_per_s,pgd_m,pgv_over_pga_s,overturn_direction",
                "false,false,,0,,,,1.0,0.0,,,,,0,0,1.0,,,6.13125,0.625,0.43,0.07,0.07,",
            ]
        );
        r.overturned = true;
        r.mode = Some(2);
        r.overturn_time = Some(0.75);
        r.peak_friction_demand = Some(0.3);
        r.lift_off = Some(false);
        (r.rocking_starts, r.chatter_impacts_summed, r.decided_at) = (1, 3, 0.5);
        r.peak_friction_demand_time = Some(0.25);
        r.friction_demand_followed_until = Some(0.6);
        r.overturn_direction = Some(-1.0);
        assert_eq!(
            lines(&th_table(&r))[1],
            "false,true,2,0,,0.75,,1.0,0.0,0.3,,false,,1,3,0.5,0.25,0.6,6.13125,0.625,0.43,0.07,0.07,-1.0"
        );
    }
}
