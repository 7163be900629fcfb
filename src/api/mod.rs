//! The HTTP API: thin glue from requests to the job store and back. No physics
//! here.

// Handlers return `Result<_, Problem>`: the error is the response body itself.
#![allow(clippy::result_large_err)]

pub mod auth;
pub mod csv;
pub mod events;
pub mod health;
pub mod http;
pub mod jobs;
pub mod page;
pub mod plot;
pub mod problem;
pub mod records;
pub mod reference;
pub mod representation;

use std::time::Duration;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::{HeaderName, HeaderValue, Method, Request, StatusCode, header};
use axum::response::IntoResponse;
use axum::routing::get;
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::compression::predicate::{DefaultPredicate, Predicate};
use tower_http::compression::{CompressionLayer, CompressionLevel};
use tower_http::cors::{AllowOrigin, CorsLayer};
use tower_http::request_id::{MakeRequestUuid, PropagateRequestIdLayer, SetRequestIdLayer};
use tower_http::set_header::SetResponseHeaderLayer;
use tower_http::timeout::{RequestBodyDeadlineLayer, TimeoutLayer};
use tower_http::trace::TraceLayer;
use utoipa::OpenApi;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use crate::service::AppState;
use problem::Problem;

/// The API description (merged with the routes' own).
#[derive(OpenApi)]
#[openapi(
    info(
        title = "topple",
        description = "Rocking and overturning of free-standing rigid blocks under cycloidal pulses (Makris & Zhang 2001). Submit a job spec, poll its status, fetch its result.",
        license(name = "MIT", identifier = "MIT")
    ),
    servers((url = "/", description = "This service (relative to where this description was fetched)")),
    components(schemas(crate::kinds::JobResult, crate::jobs::schema::Engine)),
    modifiers(&BearerScheme),
    tags(
        (name = "jobs", description = "Jobs of every kind: time histories, overturning and friction spectra, forensic queries, record spectra, fragility and survival"),
        (name = "records", description = "Accelerograms uploaded as files (PEER AT2, CSV, JSON), named by jobs"),
        (name = "operations", description = "Health, readiness, metrics")
    )
)]
pub struct ApiDoc;

/// Tenants' tokens (`--tokens-file`), or the single optional token
/// (`TOPPLE_API_TOKEN`), as a security scheme.
struct BearerScheme;

impl utoipa::Modify for BearerScheme {
    fn modify(&self, api: &mut utoipa::openapi::OpenApi) {
        use utoipa::openapi::security::{HttpAuthScheme, HttpBuilder, SecurityScheme};
        let components = api.components.get_or_insert_with(Default::default);
        components.add_security_scheme(
            "bearer",
            SecurityScheme::Http(
                HttpBuilder::new()
                    .scheme(HttpAuthScheme::Bearer)
                    .description(Some(
                        "A tenant's token. With a tokens file (`--tokens-file`: one line per token, `NAME blake3:<64 hex digits of the token's blake3 hash>`; `topple token NAME` makes a token and its line), every request needs a token except reads of /healthz, /readyz, /openapi.yaml, the API reference at /docs and the page at / (and of /metrics with `--metrics-open`) and CORS preflights; its tenant is the name its token maps to (a tenant may have several tokens), and a tenant sees only its own jobs (another tenant's id is a 404). Without a tokens file there is one tenant, `default`: with TOPPLE_API_TOKEN, POST and DELETE need that token, and reads too with TOPPLE_AUTH_READS; without it, everything is open. With both, TOPPLE_API_TOKEN is one more token of tenant `default`.",
                    ))
                    .build(),
            ),
        );
    }
}

/// Every result document carries `engine` (added where documents are made,
/// in [`crate::kinds::key::engine_doc`]): the result schemas say so.
struct EngineProvenance;

impl utoipa::Modify for EngineProvenance {
    fn modify(&self, api: &mut utoipa::openapi::OpenApi) {
        use utoipa::openapi::{RefOr, Schema};
        let Some(components) = api.components.as_mut() else {
            return;
        };
        for kind in crate::kinds::JobKind::ALL {
            let name = kind.result_schema();
            if let Some(RefOr::T(Schema::Object(o))) = components.schemas.get_mut(name.as_ref()) {
                o.properties.insert(
                    "engine".into(),
                    utoipa::openapi::Ref::from_schema_name("Engine").into(),
                );
                if !o.required.iter().any(|r| r == "engine") {
                    o.required.push("engine".into());
                }
            }
        }
    }
}

/// Routes and their OpenAPI description, from one source.
pub fn routes() -> (Router<AppState>, utoipa::openapi::OpenApi) {
    let (router, mut api) = OpenApiRouter::with_openapi(ApiDoc::openapi())
        .routes(routes!(jobs::create_job, jobs::list_jobs))
        .routes(routes!(jobs::get_job, jobs::cancel_job))
        .routes(routes!(jobs::get_result))
        .routes(routes!(jobs::cancel_only))
        .routes(routes!(events::job_events))
        .routes(routes!(plot::get_plot))
        .routes(routes!(records::create_record, records::list_records))
        .routes(routes!(records::get_record, records::delete_record))
        .routes(routes!(health::healthz))
        .routes(routes!(health::readyz))
        .routes(routes!(health::metrics))
        .split_for_parts();
    // The result schemas are known once the routes are merged in.
    utoipa::Modify::modify(&EngineProvenance, &mut api);
    crate::jobs::schema::rules::add(&mut api);
    (router, api)
}

/// The OpenAPI document as YAML (what `openapi.yaml` holds).
pub fn openapi_yaml() -> String {
    portable_floats(&openapi_document().to_yaml().unwrap_or_default())
}

/// The OpenAPI document as JSON (what the reference at `/docs` is made
/// from).
pub fn openapi_value() -> serde_json::Value {
    serde_json::to_value(openapi_document()).unwrap_or_default()
}

/// The OpenAPI document: the routes' description and `/openapi.yaml`.
fn openapi_document() -> utoipa::openapi::OpenApi {
    let (_, mut api) = routes();
    api.paths.paths.insert(
        "/openapi.yaml".into(),
        utoipa::openapi::path::PathItem::new(
            utoipa::openapi::HttpMethod::Get,
            utoipa::openapi::path::OperationBuilder::new()
                .tag("operations")
                .operation_id(Some("openapi"))
                .security(utoipa::openapi::security::SecurityRequirement::default())
                .summary(Some("This API description (OpenAPI 3.1, YAML)"))
                .response(
                    "200",
                    utoipa::openapi::ResponseBuilder::new()
                        .description("The description")
                        .content(
                            "application/yaml",
                            utoipa::openapi::ContentBuilder::new().build(),
                        )
                        .build(),
                )
                .build(),
        ),
    );
    api
}

/// The YAML with every number in exponent form written with a decimal point
/// (`1e-9` as `1.0e-9`): YAML 1.1 parsers (PyYAML) read `1e-9` as a string.
fn portable_floats(yaml: &str) -> String {
    let mut out = String::with_capacity(yaml.len() + 64);
    for line in yaml.split_inclusive('\n') {
        let body = line.trim_end_matches('\n');
        let start = match body.rfind(": ") {
            Some(i) => i + 2,
            None => match body.trim_start().strip_prefix("- ") {
                Some(rest) => body.len() - rest.len(),
                None => 0,
            },
        };
        let value = &body[start..];
        let unsigned = value.strip_prefix('-').unwrap_or(value);
        let bare_exponent = unsigned
            .split_once('e')
            .is_some_and(|(mantissa, exponent)| {
                let exponent = exponent.strip_prefix(['-', '+']).unwrap_or(exponent);
                !mantissa.is_empty()
                    && !exponent.is_empty()
                    && mantissa.bytes().all(|b| b.is_ascii_digit())
                    && exponent.bytes().all(|b| b.is_ascii_digit())
            });
        match value.find('e') {
            Some(e) if bare_exponent => {
                out.push_str(&line[..start + e]);
                out.push_str(".0");
                out.push_str(&line[start + e..]);
            }
            _ => out.push_str(line),
        }
    }
    out
}

async fn not_found() -> Problem {
    Problem::not_found("no such endpoint; see /openapi.yaml")
}

async fn method_not_allowed() -> Problem {
    Problem::new(
        StatusCode::METHOD_NOT_ALLOWED,
        "method-not-allowed",
        "Method not allowed",
        "this endpoint does not take that method; see /openapi.yaml",
    )
}

/// The whole application router.
pub fn router(state: AppState) -> Router {
    let (api, _) = routes();
    let yaml = openapi_yaml();
    let api = api
        .route("/", get(page::index))
        .route("/static/{*path}", get(page::asset))
        .route(reference::PATH, get(reference::index))
        .route(
            "/openapi.yaml",
            get(move || {
                let yaml = yaml.clone();
                async move { ([(header::CONTENT_TYPE, "application/yaml")], yaml).into_response() }
            }),
        );
    with_layers(api, state)
}

/// Wraps routes in what every request passes through: tracing, panic
/// catching, CORS, the request timeout, bare errors turned into problem+json,
/// authentication, the body limit and the body read deadline; unknown routes
/// and methods answer problem+json too.
pub fn with_layers(routes: Router<AppState>, state: AppState) -> Router {
    let max_body = state.config.max_body_bytes;
    let timeout = state.config.max_wait + Duration::from_secs(15);
    let cors = cors(&state.config.cors_origins);
    let app = routes
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(DefaultBodyLimit::max(max_body))
        .layer(RequestBodyDeadlineLayer::new(
            state.config.body_read_timeout,
        ))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            http::refuse_oversized_bodies,
        ))
        .layer(axum::middleware::from_fn_with_state(
            auth::Gate::new(state.config.clone()),
            auth::resolve_tenant,
        ))
        .layer(TimeoutLayer::with_status_code(
            StatusCode::SERVICE_UNAVAILABLE,
            timeout,
        ))
        .layer(axum::middleware::map_response(bare_errors_as_problems));
    let app = match cors {
        Some(cors) => app.layer(cors),
        None => app,
    };
    // Outermost last: a request passes the request-id layers first, so that
    // the log span, problem bodies and every response carry its id.
    app.layer(CatchPanicLayer::custom(panic_as_problem))
        .layer(axum::middleware::from_fn(http::problem_instance))
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(|req: &Request<_>| {
                    tracing::info_span!(
                        "request",
                        method = %req.method(),
                        path = %req.uri().path(),
                        request_id = req
                            .headers()
                            .get(&http::REQUEST_ID)
                            .and_then(|v| v.to_str().ok())
                            .unwrap_or(""),
                        job_id = tracing::field::Empty,
                    )
                })
                // A 5xx is logged where it arises, at the level it deserves (a
                // full disk or a database restart warns; a bug is an error):
                // the layer's own line is a warning, not an alert.
                .on_failure(tower_http::trace::DefaultOnFailure::new().level(tracing::Level::WARN)),
        )
        // Responses of known size up to 1 MiB at the usual levels; larger and
        // streamed ones (a long series, as JSON or CSV) at level 1: a brotli
        // stream at level 4 holds about 15 MB (window and hash tables), at
        // level 1 under 1 MB, and gzip's level 1 costs 6 % in size for a
        // fifth of the time of its level 6. The inner layer compresses first;
        // the outer leaves what is already encoded alone.
        .layer(
            CompressionLayer::new()
                .gzip(true)
                .br(true)
                .compress_when(DefaultPredicate::new().and(KnownSizeAtMost(1 << 20))),
        )
        .layer(
            CompressionLayer::new()
                .gzip(true)
                .br(true)
                .quality(CompressionLevel::Precise(1)),
        )
        .layer(SetResponseHeaderLayer::if_not_present(
            header::SERVER,
            HeaderValue::from_static(concat!("topple/", env!("CARGO_PKG_VERSION"))),
        ))
        .layer(PropagateRequestIdLayer::new(http::REQUEST_ID.clone()))
        .layer(SetRequestIdLayer::new(
            http::REQUEST_ID.clone(),
            MakeRequestUuid,
        ))
        .layer(axum::middleware::from_fn(http::sanitize_request_id))
        .with_state(state)
}

/// CORS for the configured origins (`*`: any); `None` without origins.
fn cors(origins: &[String]) -> Option<CorsLayer> {
    if origins.is_empty() {
        return None;
    }
    let allow = if origins.iter().any(|o| o == "*") {
        AllowOrigin::any()
    } else {
        AllowOrigin::list(
            origins
                .iter()
                .filter_map(|o| HeaderValue::from_str(o.trim()).ok()),
        )
    };
    Some(
        CorsLayer::new()
            .allow_origin(allow)
            .allow_methods([Method::GET, Method::POST, Method::DELETE])
            .allow_headers([
                header::CONTENT_TYPE,
                header::AUTHORIZATION,
                header::ACCEPT,
                header::IF_NONE_MATCH,
                http::REQUEST_ID.clone(),
                HeaderName::from_static("traceparent"),
                HeaderName::from_static("tracestate"),
            ])
            .expose_headers([
                header::ETAG,
                header::LOCATION,
                header::RETRY_AFTER,
                http::REQUEST_ID.clone(),
                header::CONTENT_DISPOSITION,
                header::WWW_AUTHENTICATE,
                header::LINK,
            ])
            .max_age(Duration::from_secs(3600)),
    )
}

/// A panic in a handler: 500 problem+json, with nothing of the panic in it.
fn panic_as_problem(_: Box<dyn std::any::Any + Send + 'static>) -> axum::response::Response {
    tracing::error!("a request handler panicked");
    Problem::internal("internal error").into_response()
}

/// Errors that layers answer with an empty body (the request timeout, say)
/// get a problem+json body.
async fn bare_errors_as_problems(response: axum::response::Response) -> axum::response::Response {
    let status = response.status();
    if !(status.is_client_error() || status.is_server_error())
        || response.headers().contains_key(header::CONTENT_TYPE)
    {
        return response;
    }
    let (title, detail) = match status {
        StatusCode::SERVICE_UNAVAILABLE => (
            "Service unavailable",
            "the request took too long; poll the job instead of waiting on it",
        ),
        _ => (
            status.canonical_reason().unwrap_or("Error"),
            "the request could not be served",
        ),
    };
    let kind = title.to_lowercase().replace(' ', "-");
    let mut problem = Problem::new(status, &kind, title, detail).into_response();
    for (name, value) in response.headers() {
        if name != header::CONTENT_LENGTH {
            problem.headers_mut().insert(name.clone(), value.clone());
        }
    }
    problem
}

/// Compresses responses whose size is known and at most this many bytes.
#[derive(Clone, Copy, Debug)]
struct KnownSizeAtMost(u64);

impl Predicate for KnownSizeAtMost {
    fn should_compress<B>(&self, response: &axum::http::Response<B>) -> bool
    where
        B: http_body::Body,
    {
        response
            .body()
            .size_hint()
            .exact()
            .is_some_and(|n| n <= self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::portable_floats;

    /// The kinds a client may list by (`GET /v1/jobs?kind=`) are an enum in
    /// the description, and exactly the kinds the server takes.
    #[test]
    fn the_kind_parameter_lists_every_kind() {
        let (_, api) = super::routes();
        let doc = serde_json::to_value(&api).expect("the description serialises");
        let kind = doc["paths"]["/v1/jobs"]["get"]["parameters"]
            .as_array()
            .and_then(|p| p.iter().find(|p| p["name"] == "kind"))
            .expect("a kind parameter");
        let reference = kind["schema"]["oneOf"]
            .as_array()
            .and_then(|o| o.iter().find_map(|s| s["$ref"].as_str()))
            .or_else(|| kind["schema"]["$ref"].as_str())
            .expect("the kind parameter refers to the kind enum");
        let name = reference.rsplit('/').next().unwrap_or("");
        let listed: Vec<&str> = doc["components"]["schemas"][name]["enum"]
            .as_array()
            .map(|e| e.iter().filter_map(|v| v.as_str()).collect())
            .unwrap_or_default();
        assert_eq!(listed, crate::kinds::KINDS);
    }

    #[test]
    fn exponent_numbers_get_a_decimal_point() {
        let yaml = "a:\n  minimum: 1e-9\n  maximum: -1e8\n  x: 1.5e-3\n  d: Width 1e-4 to 2\n  - 1e4\n  s: 'x: 1e4'\n";
        assert_eq!(
            portable_floats(yaml),
            "a:\n  minimum: 1.0e-9\n  maximum: -1.0e8\n  x: 1.5e-3\n  d: Width 1e-4 to 2\n  - 1.0e4\n  s: 'x: 1e4'\n"
        );
    }

    /// Every kind's result schema is described, with its `engine` required:
    /// the list comes from the registry, so a new kind cannot miss it.
    #[test]
    fn every_result_schema_requires_its_engine() {
        use utoipa::openapi::{RefOr, Schema};
        let (_, api) = super::routes();
        let components = api.components.expect("components");
        for kind in crate::kinds::JobKind::ALL {
            let name = kind.result_schema();
            let Some(RefOr::T(Schema::Object(o))) = components.schemas.get(name.as_ref()) else {
                panic!("no schema {name} for {kind:?}");
            };
            assert!(o.properties.contains_key("engine"), "{name}");
            assert!(o.required.iter().any(|r| r == "engine"), "{name}");
        }
    }
}
