//! What computed a result: the engine's version (part of every cache key)
//! and the `engine` provenance every result document carries.

/// The engine version as a literal (for `concat!`, e.g. `topple --version`).
#[macro_export]
macro_rules! engine_version {
    () => {
        concat!("topple-engine/", env!("CARGO_PKG_VERSION"), "/16")
    };
}

/// Version of the engine's numerics; part of every key, so that a change in
/// what the engine computes (or in what its results hold) never serves stale
/// results.
pub const ENGINE_VERSION: &str = crate::engine_version!();

/// The build's commit, when the build was told it (`TOPPLE_COMMIT` at compile
/// time: the Dockerfile and CI set it).
pub const BUILD_COMMIT: Option<&str> = option_env!("TOPPLE_COMMIT");

/// What computed a result: `{"name": "topple", "version", "numerics", "commit"?}`.
/// Every result document carries it, so a report can say what computed it.
pub fn engine_info() -> serde_json::Value {
    serde_json::to_value(engine_doc()).unwrap_or_default()
}

/// What computed a result, as every result document holds it in `engine`.
pub fn engine_doc() -> super::names::EngineDoc {
    super::names::EngineDoc {
        name: "topple".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        numerics: ENGINE_VERSION.into(),
        commit: BUILD_COMMIT.filter(|c| !c.is_empty()).map(String::from),
    }
}
