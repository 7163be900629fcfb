//! Who a request comes from: its tenant.
//!
//! With a tokens file (`--tokens-file`, see [`crate::service::tenants`])
//! every request needs `Authorization: Bearer <token>` with a token of the
//! file (or the API token, `TOPPLE_API_TOKEN`, a token of tenant `default`),
//! and its tenant is the name the token maps to; the page, the API
//! description, the health probes, CORS preflights and, with
//! `--metrics-open`, the metrics stay open.
//!
//! Without one, every request is tenant `default`; with an API token every
//! mutating request (anything but GET, HEAD and OPTIONS) needs it, and with
//! `TOPPLE_AUTH_READS` reads of jobs and metrics too.

use std::sync::Arc;

use axum::extract::{Request, State};
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::problem::Problem;
use crate::service::ServeConfig;
use crate::service::tenants::TokensFile;

/// The tenant of every request without a tokens file, and of the API token.
pub use crate::service::tenants::DEFAULT_TENANT;

/// Paths anyone may read, whatever the settings.
const OPEN: [&str; 5] = ["/healthz", "/readyz", "/openapi.yaml", "/docs", "/"];

/// The tenant a request belongs to, in its extensions (`Extension<Tenant>`).
///
/// Every request that reaches a handler has one, except requests without a
/// valid token to the routes open to all (the probes, the API description,
/// the page, the metrics when open) when the service has a tokens file.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Tenant(pub Arc<str>);

impl Tenant {
    /// The tenant's name.
    pub fn name(&self) -> &str {
        &self.0
    }
}

impl Default for Tenant {
    /// Tenant [`DEFAULT_TENANT`].
    fn default() -> Self {
        Tenant(DEFAULT_TENANT.into())
    }
}

impl std::fmt::Display for Tenant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The token of a bearer `Authorization` header: the scheme is
/// case-insensitive (RFC 9110 §11.1: `bearer`, `BEARER`), the token is what
/// follows its space, trimmed.
fn bearer(presented: Option<&HeaderValue>) -> Option<&str> {
    let (scheme, given) = presented
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim_start().split_once(' '))?;
    scheme
        .eq_ignore_ascii_case("bearer")
        .then(|| given.trim())
        .filter(|t| !t.is_empty())
}

/// Whether `presented` (the `Authorization` header) carries `token`.
///
/// Compares blake3 digests, whose equality is constant-time, so the time taken
/// says nothing about how much of a guess was right.
pub fn authorised(presented: Option<&HeaderValue>, token: &str) -> bool {
    bearer(presented)
        .is_some_and(|given| blake3::hash(given.as_bytes()) == blake3::hash(token.as_bytes()))
}

fn is_read(method: &Method) -> bool {
    method == Method::GET || method == Method::HEAD
}

/// Whether a request may pass without a token whatever the settings: a CORS
/// preflight, or a read of the page, the description, the probes (and the
/// metrics when `--metrics-open`).
fn open_to_all(config: &ServeConfig, method: &Method, path: &str) -> bool {
    method == Method::OPTIONS
        || (is_read(method)
            && (OPEN.contains(&path)
                || path.starts_with("/static/")
                || (config.metrics_open && path == "/metrics")))
}

/// Without a tokens file: whether the request needs the API token.
fn needs_api_token(config: &ServeConfig, method: &Method, path: &str) -> bool {
    if config.api_token.is_none() || open_to_all(config, method, path) {
        return false;
    }
    !is_read(method) || config.auth_reads
}

/// What decides the tenant of each request.
#[derive(Clone, Debug)]
pub struct Gate {
    config: Arc<ServeConfig>,
    tokens: Option<Arc<TokensFile>>,
}

impl Gate {
    /// The gate of a service with `config`: its tokens file is read now
    /// (one that cannot be read or parsed is logged, and accepts no token
    /// but the API token until it is fixed; `topple serve` refuses to start
    /// with it).
    pub fn new(config: Arc<ServeConfig>) -> Gate {
        let tokens = config
            .tokens_file
            .as_deref()
            .map(|path| Arc::new(TokensFile::open_or_empty(path, config.api_token.as_deref())));
        Gate { config, tokens }
    }

    /// The request's tenant (`None`: an open route without a valid token),
    /// or `Err` if it needs a token it does not carry.
    fn tenant(
        &self,
        method: &Method,
        path: &str,
        authorization: Option<&HeaderValue>,
    ) -> Result<Option<Tenant>, Unauthorized> {
        let Some(tokens) = &self.tokens else {
            if needs_api_token(&self.config, method, path) {
                let token = self.config.api_token.as_deref().unwrap_or_default();
                if !authorised(authorization, token) {
                    return Err(Unauthorized);
                }
            }
            return Ok(Some(Tenant::default()));
        };
        if open_to_all(&self.config, method, path) {
            return Ok(None);
        }
        bearer(authorization)
            .and_then(|token| tokens.tenant_of(token))
            .map(|name| Some(Tenant(name)))
            .ok_or(Unauthorized)
    }
}

/// A request without the token it needs.
#[derive(Debug)]
struct Unauthorized;

impl IntoResponse for Unauthorized {
    fn into_response(self) -> Response {
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
        r
    }
}

/// Middleware: puts the request's [`Tenant`] in its extensions, or answers
/// 401 problem+json if it needs a token it does not carry.
pub async fn resolve_tenant(State(gate): State<Gate>, mut req: Request, next: Next) -> Response {
    match gate.tenant(
        req.method(),
        req.uri().path(),
        req.headers().get(header::AUTHORIZATION),
    ) {
        Ok(Some(tenant)) => {
            req.extensions_mut().insert(tenant);
        }
        Ok(None) => {}
        Err(unauthorized) => return unauthorized.into_response(),
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

#[cfg(test)]
mod gate_tests {
    use super::*;
    use crate::service::tenants::digest;

    fn gate(configure: impl FnOnce(&mut ServeConfig)) -> Gate {
        let mut config = ServeConfig::default();
        configure(&mut config);
        Gate::new(Arc::new(config))
    }

    fn tenant_of(
        gate: &Gate,
        method: Method,
        path: &str,
        auth: Option<&'static str>,
    ) -> Result<Option<String>, Unauthorized> {
        let auth = auth.map(HeaderValue::from_static);
        gate.tenant(&method, path, auth.as_ref())
            .map(|t| t.map(|t| t.name().to_string()))
    }

    #[test]
    fn without_a_tokens_file_everyone_is_tenant_default_as_before() {
        let open = gate(|_| {});
        for (method, path) in [
            (Method::GET, "/v1/jobs"),
            (Method::POST, "/v1/jobs"),
            (Method::DELETE, "/v1/jobs/x"),
            (Method::GET, "/metrics"),
        ] {
            let t = tenant_of(&open, method, path, None).expect("open");
            assert_eq!(t.as_deref(), Some(DEFAULT_TENANT));
        }
        let token = gate(|c| c.api_token = Some("s3cret".into()));
        assert!(tenant_of(&token, Method::POST, "/v1/jobs", None).is_err());
        assert!(tenant_of(&token, Method::POST, "/v1/jobs", Some("Bearer nope")).is_err());
        let ok = tenant_of(&token, Method::POST, "/v1/jobs", Some("bearer s3cret"));
        assert_eq!(ok.expect("token").as_deref(), Some(DEFAULT_TENANT));
        assert!(tenant_of(&token, Method::GET, "/v1/jobs", None).is_ok());
        let reads = gate(|c| {
            c.api_token = Some("s3cret".into());
            c.auth_reads = true;
        });
        assert!(reads.config.reads_need_token());
        assert!(tenant_of(&reads, Method::GET, "/v1/jobs", None).is_err());
        assert!(tenant_of(&reads, Method::GET, "/metrics", None).is_err());
        assert!(tenant_of(&reads, Method::GET, "/healthz", None).is_ok());
        assert!(tenant_of(&reads, Method::OPTIONS, "/v1/jobs", None).is_ok());
        let metrics = gate(|c| {
            c.api_token = Some("s3cret".into());
            c.auth_reads = true;
            c.metrics_open = true;
        });
        assert!(tenant_of(&metrics, Method::GET, "/metrics", None).is_ok());
        assert!(tenant_of(&metrics, Method::POST, "/metrics", None).is_err());
    }

    #[test]
    fn with_a_tokens_file_every_route_but_the_open_ones_needs_a_tenants_token() {
        let path = std::env::temp_dir().join(format!(
            "topple-gate-{}-{}",
            std::process::id(),
            uuid::Uuid::now_v7()
        ));
        std::fs::write(
            &path,
            format!("alice {}\nbob {}\n", digest("tpl_a"), digest("tpl_b")),
        )
        .expect("write");
        let gate = gate(|c| {
            c.tokens_file = Some(path.clone());
            c.api_token = Some("s3cret".into());
        });
        assert!(gate.config.reads_need_token());
        for method in [Method::GET, Method::POST, Method::DELETE, Method::HEAD] {
            for path in ["/v1/jobs", "/v1/jobs/x/result", "/metrics", "/nowhere"] {
                assert!(tenant_of(&gate, method.clone(), path, None).is_err());
                assert!(tenant_of(&gate, method.clone(), path, Some("Bearer tpl_c")).is_err());
                assert!(tenant_of(&gate, method.clone(), path, Some("Basic tpl_a")).is_err());
            }
        }
        for (auth, tenant) in [
            ("Bearer tpl_a", "alice"),
            ("BEARER  tpl_b ", "bob"),
            ("Bearer s3cret", DEFAULT_TENANT),
        ] {
            let t = tenant_of(&gate, Method::POST, "/v1/jobs", Some(auth));
            assert_eq!(t.expect("valid").as_deref(), Some(tenant), "{auth}");
        }
        for path in ["/healthz", "/readyz", "/openapi.yaml", "/docs", "/"] {
            assert_eq!(tenant_of(&gate, Method::GET, path, None).ok(), Some(None));
        }
        assert_eq!(
            tenant_of(&gate, Method::OPTIONS, "/v1/jobs", None).ok(),
            Some(None)
        );
        let _ = std::fs::remove_file(&path);
    }
}
