//! A tenant's access to a test server: a tokens file admitting tenants,
//! and requests carrying a tenant's token.

use std::path::{Path, PathBuf};

/// A tenant's token and the line of the tokens file that admits it.
pub fn token_line(name: &str) -> (String, String) {
    let token = format!("tpl_{}", uuid::Uuid::now_v7().simple());
    let digest = blake3::hash(token.as_bytes()).to_hex();
    (token, format!("{name} blake3:{digest}"))
}

/// Writes a tokens file for `names` in `dir`; returns it and the tokens.
pub fn tokens_file(dir: &Path, names: &[&str]) -> (PathBuf, Vec<String>) {
    let mut lines = vec!["# tenants of this test".to_string()];
    let mut tokens = Vec::new();
    for name in names {
        let (token, line) = token_line(name);
        lines.push(line);
        tokens.push(token);
    }
    let path = dir.join("tokens");
    std::fs::write(&path, lines.join("\n") + "\n").expect("tokens file");
    (path, tokens)
}

/// Requests to one server on behalf of one tenant (or of none).
#[derive(Clone)]
pub struct Tenant {
    http: reqwest::Client,
    base: String,
    token: Option<String>,
}

impl Tenant {
    /// The tenant of `token` on the server at `base`.
    pub fn new(base: &str, token: Option<&str>) -> Self {
        Tenant {
            http: reqwest::Client::new(),
            base: base.to_string(),
            token: token.map(str::to_string),
        }
    }

    /// A request of `path` with the tenant's token.
    pub fn request(&self, method: reqwest::Method, path: &str) -> reqwest::RequestBuilder {
        let r = self.http.request(method, format!("{}{path}", self.base));
        match &self.token {
            Some(t) => r.bearer_auth(t),
            None => r,
        }
    }
}
