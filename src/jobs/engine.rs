//! What computed a result: the engine's version (part of every cache key)
//! and the `engine` provenance every result document carries.

/// The engine version as a literal (for `concat!`, e.g. `topple --version`).
#[macro_export]
macro_rules! engine_version {
    () => {
        concat!("topple-engine/", env!("CARGO_PKG_VERSION"), "/14")
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
    let mut info = serde_json::json!({
        "name": "topple",
        "version": env!("CARGO_PKG_VERSION"),
        "numerics": ENGINE_VERSION,
    });
    if let Some(commit) = BUILD_COMMIT.filter(|c| !c.is_empty()) {
        info["commit"] = commit.into();
    }
    info
}

/// `doc` with its `engine` provenance.
pub fn with_engine(mut doc: serde_json::Value) -> serde_json::Value {
    if let Some(o) = doc.as_object_mut() {
        o.insert("engine".into(), engine_info());
    }
    doc
}
