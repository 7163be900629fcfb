//! What the figures of result documents are drawn with (plotters, SVG
//! backend: no system fonts needed): style, bands, time panels, windows, a
//! figure's frame ([`render`]) and the notes several figures carry. Each
//! kind's figure is in its folder (`src/kinds/<kind>/figure.rs`), drawn with
//! these; `JobResult::figure` picks it.

pub mod bands;
pub mod precision;
pub mod style;
pub mod time_panel;
pub mod window;

use plotters::prelude::*;

use crate::dynamics::PulseShape;
use crate::jobs::spec::BlockNorm;

pub use precision::precision_diagram;
use style::{Area, Drawn, INK, TITLE};
pub use window::Window;

/// Revision of the figures' drawing: part of a figure's entity tag, so a
/// figure cached under an older drawing is not taken for the new one.
pub const FIGURES_REVISION: u32 = 8;

/// Why a figure cannot be drawn.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FigureError {
    /// The result has nothing to draw, or is not a result (the text says why).
    Result(String),
    /// A window was asked of a result that has no time axis.
    Window(String),
}

impl std::fmt::Display for FigureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FigureError::Result(e) | FigureError::Window(e) => f.write_str(e),
        }
    }
}

impl std::error::Error for FigureError {}

/// Draws a `width` × `height` figure titled `title` with `draw` and returns
/// its SVG text.
pub(crate) fn render(
    (width, height): (u32, u32),
    title: &str,
    draw: impl FnOnce(&Area) -> Drawn,
) -> Result<String, String> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        let drawn = (|| -> Drawn {
            root.fill(&WHITE)?;
            let area = root.titled(title, style::text(TITLE, INK))?;
            draw(&area)?;
            root.present()?;
            Ok(())
        })();
        drawn.map_err(|e| format!("cannot draw the figure: {e}"))?;
    }
    Ok(out)
}

/// How a pulse family reads in a title: "one-sine", "Type-C2".
pub(crate) fn shape_title(shape: PulseShape) -> String {
    match shape {
        PulseShape::OneSine => "one-sine".into(),
        PulseShape::OneCosine => "one-cosine".into(),
        PulseShape::HalfSine => "half-sine".into(),
        PulseShape::Rectangular => "rectangular".into(),
        PulseShape::Ricker { symmetric: false } => "antisymmetric Ricker".into(),
        PulseShape::Ricker { symmetric: true } => "Ricker".into(),
        PulseShape::MavroeidisPapageorgiou { gamma, nu } => format!(
            "Mavroeidis–Papageorgiou (γ\u{a0}=\u{a0}{}, ν\u{a0}=\u{a0}{}\u{a0}rad)",
            style::fmt_num(gamma.get(), 3),
            style::fmt_num(nu.get(), 3)
        ),
        PulseShape::Cn(n) => format!("Type-C{n}"),
    }
}

/// "α = 0.25 rad, p = 2.14 rad/s, η = 0.9" (and μ when given) of a block.
pub(crate) fn block_text(b: &BlockNorm) -> String {
    let mut parts = vec![
        format!("α\u{a0}=\u{a0}{}\u{a0}rad", style::fmt_num(b.alpha, 3)),
        format!("p\u{a0}=\u{a0}{}\u{a0}rad/s", style::fmt_num(b.p, 3)),
        format!("η\u{a0}=\u{a0}{}", style::fmt_num(b.eta, 3)),
    ];
    if let Some(m) = b.mu {
        parts.push(format!("μ\u{a0}=\u{a0}{}", style::fmt_num(m, 3)));
    }
    parts.join(", ")
}

/// The vertical motion of a kind that scales its ground motion, as its
/// figures name it: "ü_v = r ü_g", a pulse of its own (a_v = k a_p; ω_v
/// absolute or relative to ω_p; its delay), or a record's own vertical
/// samples (their unscaled peak, in g of `g` m/s²).
pub(crate) fn scaled_vertical_text(v: &crate::jobs::vertical::ScaledVertical, g: f64) -> String {
    use crate::jobs::vertical::ScaledVertical;
    use crate::spectrum::overturning::VerticalFrequency;
    use style::fmt_num;
    match v {
        ScaledVertical::Ratio(r) => format!("ü_v = {} ü_g", fmt_num(*r, 3)),
        ScaledVertical::Pulse(v) => format!(
            "ü_v: a {} pulse, a_v = {} a_p, {}{}",
            shape_title(v.shape),
            fmt_num(v.amplitude_ratio, 3),
            match v.frequency {
                VerticalFrequency::Omega(w) => format!("ω_v = {} rad/s", fmt_num(w, 4)),
                VerticalFrequency::Ratio(x) => format!("ω_v = {} ω_p", fmt_num(x, 4)),
            },
            if v.delay > 0.0 {
                format!(", {} s later", fmt_num(v.delay, 4))
            } else {
                String::new()
            }
        ),
        ScaledVertical::Samples(s) => format!(
            "ü_v: the record's own vertical, scaled with it (PGA_v {} g unscaled)",
            fmt_num(crate::records::pga(s) / g, 4)
        ),
    }
}

/// The same vertical motion as a title names it, short enough for one line
/// (the legend gives [`scaled_vertical_text`]): "ü_v = r ü_g", "with a
/// vertical pulse of its own" or "with the record's own vertical".
pub(crate) fn scaled_vertical_title(v: &crate::jobs::vertical::ScaledVertical) -> String {
    use crate::jobs::vertical::ScaledVertical;
    match v {
        ScaledVertical::Ratio(r) => format!("ü_v = {} ü_g", style::fmt_num(*r, 3)),
        ScaledVertical::Pulse(_) => "with a vertical pulse of its own".into(),
        ScaledVertical::Samples(_) => "with the record's own vertical".into(),
    }
}

/// The note naming a Coulomb floor: "floor: Coulomb friction, μ = 0.3", with
/// μ_k when it differs.
pub fn floor_note(contact: &crate::jobs::contact::ContactNorm) -> String {
    if contact.mu_kinetic < contact.mu {
        format!(
            "floor: Coulomb friction, μ = {} (static), μ_k = {} (kinetic)",
            style::fmt_num(contact.mu, 3),
            style::fmt_num(contact.mu_kinetic, 3)
        )
    } else {
        format!(
            "floor: Coulomb friction, μ = {}",
            style::fmt_num(contact.mu, 3)
        )
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::dynamics::excitation::Real;
    use crate::kinds::JobResult;
    use serde_json::Value;

    /// The result `topple run` prints for the spec `text`.
    pub(crate) fn computed(text: &str) -> Value {
        crate::kinds::Job::parse(text)
            .expect("a valid spec")
            .run(&crate::spectrum::Control::new())
            .expect("it runs")
    }

    /// The points (px) of each `element` (`polygon`, `polyline`) of `svg`
    /// whose tag contains `needle` (e.g. `fill="#009669"`; "" for all).
    pub(crate) fn shapes(svg: &str, element: &str, needle: &str) -> Vec<Vec<(f64, f64)>> {
        let open = format!("<{element} ");
        svg.split(&open)
            .skip(1)
            .filter_map(|rest| rest.split('>').next())
            .filter(|tag| tag.contains(needle))
            .filter_map(|tag| tag.split("points=\"").nth(1)?.split('"').next())
            .map(|points| {
                points
                    .split_whitespace()
                    .filter_map(|xy| {
                        let (x, y) = xy.split_once(',')?;
                        Some((x.parse().ok()?, y.parse().ok()?))
                    })
                    .collect()
            })
            .collect()
    }

    /// `#RRGGBB` of a colour, as the SVG writes it.
    /// The words an SVG shows, in document order, lines wrapped by the
    /// legend joined by a space.
    pub(crate) fn words(svg: &str) -> String {
        svg.split('>')
            .filter_map(|piece| piece.split('<').next())
            .flat_map(str::split_whitespace)
            .collect::<Vec<_>>()
            .join(" ")
    }

    pub(crate) fn hex(c: RGBColor) -> String {
        format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
    }

    /// The least and largest x of `shapes`.
    pub(crate) fn x_extent(shapes: &[Vec<(f64, f64)>]) -> (f64, f64) {
        shapes
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.0), hi.max(p.0))
            })
    }

    /// The result of a spec, typed.
    pub(crate) fn typed(text: &str) -> JobResult {
        JobResult::from_value(computed(text)).expect("a result of its kind")
    }

    #[test]
    fn a_window_is_for_time_histories_only() {
        let w = Window::new(0.0, 1.0).expect("window");
        let doc = typed(include_str!("../../specs/one_cosine_friction.json"));
        let e = doc.figure(Some(w)).unwrap_err();
        assert!(
            matches!(&e, FigureError::Window(text) if text.contains("friction spectrum")),
            "{e:?}"
        );
    }

    #[test]
    fn names() {
        let real = |x: f64| Real::new(x).expect("finite");
        for (shape, title) in [
            (PulseShape::Cn(2), "Type-C2"),
            (PulseShape::OneSine, "one-sine"),
            (
                PulseShape::Ricker { symmetric: false },
                "antisymmetric Ricker",
            ),
            (PulseShape::Ricker { symmetric: true }, "Ricker"),
            (
                PulseShape::MavroeidisPapageorgiou {
                    gamma: real(2.5),
                    nu: real(1.5),
                },
                "Mavroeidis–Papageorgiou (γ = 2.5, ν = 1.5 rad)",
            ),
        ] {
            assert_eq!(shape_title(shape).replace('\u{a0}', " "), title);
        }
        let mut b = BlockNorm {
            alpha: 0.25,
            p: 2.14,
            eta: 0.9,
            mu: None,
            g: 9.81,
        };
        assert_eq!(
            block_text(&b).replace('\u{a0}', " "),
            "α = 0.25 rad, p = 2.14 rad/s, η = 0.9"
        );
        b.mu = Some(0.7);
        assert!(block_text(&b).replace('\u{a0}', " ").ends_with(", μ = 0.7"));
    }
}
