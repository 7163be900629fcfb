//! The web page at `/`: a form that submits jobs, follows them and shows
//! their plots. One self-contained HTML document (inline style and script).

use axum::http::header;
use axum::response::IntoResponse;

/// The page, as served.
pub const HTML: &str = include_str!("page.html");

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
        HTML,
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

    #[test]
    fn the_form_offers_every_kind_of_job() {
        for kind in crate::jobs::KINDS {
            let radio = format!(r#"<input type="radio" name="kind" value="{kind}""#);
            assert!(HTML.contains(&radio), "the form has no {kind}");
        }
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
