//! The web page at `/` as the server sends it: the markup under its policy,
//! and every file it names under /static/ with its content type, open to
//! readers without a token. What the page does is tested in a browser
//! (tests/e2e/page_test.py).

use super::helpers::*;

/// The paths under /static/ the markup names (`src="…"`, `href="…"`).
fn static_paths(html: &str) -> Vec<String> {
    html.split("=\"/static/")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .map(|path| format!("/static/{path}"))
        .collect()
}

#[tokio::test]
async fn the_page_and_its_files_are_served_with_their_types_under_a_strict_policy() {
    // Reads need the token here: the page and its files do not.
    let app = spawn_app_with("page", |c| {
        c.api_token = Some("s3cret".into());
        c.auth_reads = true;
    })
    .await;
    let r = app.client.get(app.url("/")).send().await.expect("page");
    assert_eq!(r.status().as_u16(), 200);
    assert_eq!(r.headers()["content-type"], "text/html; charset=utf-8");
    let csp = r.headers()["content-security-policy"]
        .to_str()
        .expect("policy")
        .to_string();
    for directive in [
        "default-src 'self'",
        "script-src 'self'",
        "style-src 'self'",
        "connect-src 'self'",
    ] {
        assert!(csp.contains(directive), "{csp}");
    }
    assert!(!csp.contains("unsafe"), "{csp}");
    let html = r.text().await.expect("html");
    let paths = static_paths(&html);
    assert!(paths.contains(&"/static/main.js".to_string()), "{paths:?}");
    assert!(
        paths.contains(&"/static/style.css".to_string()),
        "{paths:?}"
    );
    assert!(
        paths.contains(&"/static/constants.js".to_string()),
        "{paths:?}"
    );
    for path in &paths {
        let r = app.client.get(app.url(path)).send().await.expect("file");
        assert_eq!(r.status().as_u16(), 200, "{path}");
        let want = if path.ends_with(".css") {
            "text/css; charset=utf-8"
        } else {
            "text/javascript; charset=utf-8"
        };
        assert_eq!(r.headers()["content-type"], want, "{path}");
        assert_eq!(r.headers()["cache-control"], "no-cache", "{path}");
        assert_eq!(r.headers()["x-content-type-options"], "nosniff", "{path}");
        let tag = r.headers()["etag"].clone();
        // Checked again before use: unchanged, it is not sent again.
        let again = app
            .client
            .get(app.url(path))
            .header("if-none-match", tag)
            .send()
            .await
            .expect("file again");
        assert_eq!(again.status().as_u16(), 304, "{path}");
    }
    // The constants come from the service's own.
    let (_, _, constants) = app.get_text("/static/constants.js").await;
    assert!(constants.contains("export const G = 9.81;"), "{constants}");
    assert!(
        constants.contains("export const MAX_OBSERVATIONS = 32;"),
        "{constants}"
    );
    // A file the page does not have is a problem, not the page.
    let (status, ct, _) = app.get_text("/static/nope.js").await;
    assert_eq!(status, 404);
    assert!(ct.starts_with("application/problem+json"), "{ct}");
    app.stop().await;
}
