//! Optional bearer-token authentication.
//!
//! With a token configured (`TOPPLE_API_TOKEN`), every mutating request
//! (anything but GET, HEAD and OPTIONS) needs `Authorization: Bearer <token>`;
//! with `TOPPLE_AUTH_READS` reads of jobs and metrics need it too. The page,
//! the API description and the health probes stay open.

use axum::extract::{Request, State};
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::problem::Problem;
use crate::service::AppState;

/// The tenant a request acts for.
#[derive(Clone, Debug)]
pub struct Tenant(pub std::sync::Arc<str>);

impl Tenant {
    /// Its name.
    pub fn name(&self) -> &str {
        &self.0
    }
}

/// The tenant of a service without a tokens file.
pub const DEFAULT_TENANT: &str = "default";

/// Paths anyone may read, whatever the settings.
const OPEN: [&str; 4] = ["/healthz", "/readyz", "/openapi.yaml", "/"];

/// Whether `presented` (the `Authorization` header) carries `token`.
///
/// Compares blake3 digests, whose equality is constant-time, so the time taken
/// says nothing about how much of a guess was right.
pub fn authorised(presented: Option<&HeaderValue>, token: &str) -> bool {
    // The scheme is case-insensitive (RFC 9110 §11.1): `bearer`, `BEARER`.
    let Some((scheme, given)) = presented
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim_start().split_once(' '))
    else {
        return false;
    };
    if !scheme.eq_ignore_ascii_case("bearer") {
        return false;
    }
    blake3::hash(given.trim().as_bytes()) == blake3::hash(token.as_bytes())
}

fn needs_token(state: &AppState, method: &Method, path: &str) -> bool {
    if state.config.api_token.is_none() || method == Method::OPTIONS {
        return false;
    }
    let read = method == Method::GET || method == Method::HEAD;
    if !read {
        return true;
    }
    state.config.auth_reads && !OPEN.contains(&path) && !path.starts_with("/static/")
}

/// Middleware: 401 problem+json unless the request may pass.
pub async fn require_token(
    State(state): State<AppState>,
    mut req: Request,
    next: Next,
) -> Response {
    req.extensions_mut()
        .insert(Tenant(std::sync::Arc::from(DEFAULT_TENANT)));
    if needs_token(&state, req.method(), req.uri().path()) {
        let token = state.config.api_token.as_deref().unwrap_or_default();
        if !authorised(req.headers().get(header::AUTHORIZATION), token) {
            let mut r = Problem::new(
                StatusCode::UNAUTHORIZED,
                "unauthorized",
                "Unauthorized",
                "this request needs the header `Authorization: Bearer <token>` with the service's API token",
            )
            .header_name("authorization")
            .into_response();
            r.headers_mut().insert(
                header::WWW_AUTHENTICATE,
                HeaderValue::from_static("Bearer realm=\"topple\""),
            );
            return r;
        }
    }
    next.run(req).await
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_exact_bearer_token_passes() {
        for ok in [
            "Bearer s3cret",
            "bearer s3cret",
            "BEARER s3cret",
            "beaRer  s3cret",
        ] {
            assert!(
                authorised(Some(&HeaderValue::from_static(ok)), "s3cret"),
                "{ok}"
            );
        }
        for bad in [
            "Bearer s3cre",
            "Bearer s3cret2",
            "Basic s3cret",
            "s3cret",
            "Bearer ",
            "Bearers s3cret",
            "Bearer\ts3cret",
        ] {
            assert!(
                !authorised(Some(&HeaderValue::from_static(bad)), "s3cret"),
                "{bad}"
            );
        }
        assert!(!authorised(None, "s3cret"));
    }
}
