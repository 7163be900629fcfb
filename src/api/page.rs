//! The web page at `/`: a form that submits jobs, follows them and shows
//! their plots. One self-contained HTML document (inline style and script).

use std::sync::LazyLock;

use axum::http::header;
use axum::response::IntoResponse;

use crate::kinds::JobKind;

/// The page's source: [`KINDS_MARK`] stands where the kinds are listed.
const TEMPLATE: &str = include_str!("page.html");

/// The line of [`TEMPLATE`] that the kinds' radio buttons replace.
const KINDS_MARK: &str = "<!-- job kinds -->\n";

/// The page, as served: its kind list is the registry's
/// ([`crate::kinds::registry`]), the first kind checked.
pub static HTML: LazyLock<String> = LazyLock::new(|| {
    let radios: String = JobKind::ALL
        .iter()
        .enumerate()
        .map(|(i, kind)| {
            format!(
                "      <label><input type=\"radio\" name=\"kind\" value=\"{}\"{}> {}</label>\n",
                kind.name(),
                if i == 0 { " checked" } else { "" },
                kind.label()
            )
        })
        .collect();
    TEMPLATE.replacen(KINDS_MARK, &radios, 1)
});

/// The policy the page runs under: its own inline style and script, requests
/// to this origin only, images from here or `data:` URLs.
pub const CSP: &str = "default-src 'self'; img-src 'self' data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'; connect-src 'self'";

/// `GET /`: the page.
pub async fn index() -> impl IntoResponse {
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CONTENT_SECURITY_POLICY, CSP),
        ],
        HTML.as_str(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn served_as_html_under_the_policy() {
        let response = index().await.into_response();
        let headers = response.headers();
        assert_eq!(headers[header::CONTENT_TYPE], "text/html; charset=utf-8");
        assert_eq!(headers[header::CONTENT_SECURITY_POLICY], CSP);
    }

    /// Every kind of the registry is offered, and has a part of the form
    /// of its own (`data-kinds` naming it, a fieldset or a field).
    #[test]
    fn the_form_offers_every_kind_of_job() {
        assert!(TEMPLATE.contains(KINDS_MARK));
        for kind in crate::kinds::KINDS {
            let radio = format!(r#"<input type="radio" name="kind" value="{kind}""#);
            assert!(HTML.contains(&radio), "the form has no {kind}");
            let form = HTML.split("data-kinds=\"").skip(1).any(|rest| {
                rest.split('"')
                    .next()
                    .is_some_and(|list| list.split(' ').any(|k| k == *kind))
            });
            assert!(form, "no part of the form is for {kind}");
        }
    }

    /// The floor's models offered are the ones the service takes, for the
    /// kinds that take a floor (time histories, spectra, forensic queries,
    /// record spectra, fragility): the fieldset is shown for those kinds,
    /// the script sends a floor for those kinds, and the service takes each
    /// model from each of them.
    #[test]
    fn the_form_offers_the_contact_models_the_service_takes() {
        let kinds = [
            "time_history",
            "spectrum",
            "forensic",
            "record_spectrum",
            "fragility",
        ];
        let fieldset = HTML
            .split("<fieldset id=\"fs-contact\"")
            .nth(1)
            .and_then(|rest| rest.split("</fieldset>").next())
            .expect("a fieldset for the floor");
        assert!(fieldset.starts_with(&format!(" data-form data-kinds=\"{}\"", kinds.join(" "))));
        let quoted: Vec<String> = kinds.iter().map(|k| format!("\"{k}\"")).collect();
        assert!(HTML.contains(&format!("const FLOOR_KINDS = [{}];", quoted.join(", "))));
        for id in ["f-c-mu", "f-c-muk"] {
            assert!(fieldset.contains(&format!("id=\"{id}\"")), "no {id}");
        }
        let models: Vec<&str> = fieldset
            .split("name=\"contact\" value=\"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .collect();
        assert_eq!(models, ["no_sliding", "coulomb"]);
        let on_floor = HTML
            .split("function withFloor(spec, k) {")
            .nth(1)
            .and_then(|rest| rest.split("\n  }").next())
            .expect("the floor's part of the spec");
        for sent in [
            "spec.contact = { model: \"coulomb\", mu: num(\"f-c-mu\") };",
            "spec.formulation = \"nonlinear\";",
            "if (k === \"spectrum\") spec.no_sliding_beside = true;",
        ] {
            assert!(on_floor.contains(sent), "{on_floor}");
        }
        let block = serde_json::json!({"alpha": 0.25, "p": 2.14});
        let specs = [
            serde_json::json!({"kind": "time_history", "block": block,
                "pulse": {"type": "one_sine", "omega_ratio": 3, "a_p_alpha_g": 4}}),
            serde_json::json!({"kind": "spectrum", "block": block,
                "pulse": {"type": "one_sine"}, "omega_ratio": {"from": 1, "to": 2, "steps": 1}}),
            serde_json::json!({"kind": "forensic", "pulse": {"type": "one_sine"},
                "frequency_hz": [1.0], "a_p_g": {"from": 0.05, "to": 0.3},
                "observations": [{"name": "a", "overturned": true, "block": block}]}),
            serde_json::json!({"kind": "record_spectrum", "block": {"alpha": 0.25},
                "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, 0.5, 0.2, -0.4, 0.0]},
                "R_m": {"from": 0.5, "to": 2, "steps": 2}, "scale": {"to": 2}}),
            serde_json::json!({"kind": "fragility", "block": block,
                "pulse": {"type": "one_sine", "frequency_hz": 1.0}, "im": "pga_g",
                "stripes": {"from": 0.1, "to": 0.5, "steps": 2}, "samples": 4, "seed": 1}),
        ];
        for model in models {
            let mut contact = serde_json::json!({"model": model});
            if model == "coulomb" {
                contact["mu"] = serde_json::json!(0.3);
            }
            for base in &specs {
                let mut spec = base.clone();
                spec["formulation"] = serde_json::json!("nonlinear");
                spec["contact"] = contact.clone();
                let kind = spec["kind"].as_str().unwrap_or_default().to_string();
                // A spectrum on the floor is sent with pure rocking's beside it.
                if kind == "spectrum" && model == "coulomb" {
                    spec["no_sliding_beside"] = serde_json::json!(true);
                }
                let taken = crate::kinds::Job::parse(&spec.to_string());
                assert!(taken.is_ok(), "{kind} on {model}: {:?}", taken.err());
            }
        }
    }

    /// A time history on a Coulomb floor is sent `outputs.series` (the
    /// field the page uses for pure rocking, shown under Coulomb too) and
    /// no `outputs.duration` (its field hidden, its value not sent): the
    /// service takes the one and refuses the other.
    #[test]
    fn the_form_sends_a_coulomb_history_its_series_and_no_end() {
        let branch = HTML
            .split("if (k === \"time_history\") {\n      if (spec.pulse)")
            .nth(1)
            .and_then(|rest| rest.split("} else if (k === \"spectrum\")").next())
            .expect("the time history's part of the spec");
        let series = "spec.outputs = { series: num(\"f-series\") };";
        let (before, _) = branch.split_once(series).expect("a series sent");
        // Sent whatever the floor: no test of it before.
        assert!(!before.contains("coulomb"), "{before}");
        let duration = branch
            .lines()
            .find(|l| l.contains("spec.outputs.duration ="))
            .expect("a duration sent");
        assert!(duration.contains("!coulomb &&"), "{duration}");
        // The form: the series' field shown under Coulomb, the duration's hidden.
        assert!(
            HTML.contains("<div class=\"field\" id=\"duration-field\"><label for=\"f-duration\">")
        );
        assert!(HTML.contains("$(\"duration-field\").hidden = coulomb;"));
        assert!(!HTML.contains("$(\"th-outputs\").hidden"));
        assert!(!HTML.contains("(no series)"));
        // The spec the form builds on a Coulomb floor, with the series field's
        // default, is taken; with a duration it would be refused.
        let default = HTML
            .split("<input id=\"f-series\"")
            .nth(1)
            .and_then(|rest| rest.split("value=\"").nth(1))
            .and_then(|rest| rest.split('"').next())
            .and_then(|v| v.parse::<u32>().ok())
            .expect("the series' default");
        let spec = |outputs: serde_json::Value| {
            serde_json::json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
                "pulse": {"type": "one_sine", "omega_ratio": 3, "a_p_alpha_g": 4},
                "formulation": "nonlinear", "contact": {"model": "coulomb", "mu": 0.3},
                "outputs": outputs})
            .to_string()
        };
        let taken = crate::kinds::Job::parse(&spec(serde_json::json!({"series": default})));
        assert!(taken.is_ok(), "{:?}", taken.err());
        let refused = spec(serde_json::json!({"series": default, "duration": 4}));
        assert!(crate::kinds::Job::parse(&refused).is_err());
    }

    #[test]
    fn self_contained() {
        for external in [
            "src=\"http",
            "href=\"http",
            "src=\"//",
            "href=\"//",
            "@import",
            "url(",
        ] {
            assert!(!HTML.contains(external), "the page refers to {external}…");
        }
    }
}
