//! Renderings of result documents in memory: a CSV table or a figure made
//! from a result is made once. Results never change, and results of one
//! cache key are the same document, so a rendering is named by the key and
//! the representation's name (which carries the figures' revision and
//! window). Who may read it is decided before, by the job it is read
//! through.

use std::sync::{Arc, Mutex};

use super::lru::Lru;

/// Most bytes of renderings held.
pub const MEMORY: usize = 32 << 20;

/// Renderings larger than this are made for each request.
pub const MAX_RENDERING: usize = 1 << 20;

/// A rendering: its bytes and what the response says of it beside them.
#[derive(Debug)]
pub struct Rendering {
    /// The body.
    pub body: Arc<[u8]>,
    /// The result's kind (a CSV table's file is named after it).
    pub kind: String,
}

/// A result's cache key and a representation's name.
type Name = (Arc<str>, String);

/// Renderings by cache key and representation.
#[derive(Debug)]
pub struct Renderings {
    inner: Mutex<Lru<Name, Arc<Rendering>>>,
}

impl Default for Renderings {
    fn default() -> Self {
        Renderings {
            inner: Mutex::new(Lru::new(MEMORY)),
        }
    }
}

impl Renderings {
    /// The rendering `format` of the result of cache key `key`, if held.
    pub fn get(&self, key: &Arc<str>, format: &str) -> Option<Arc<Rendering>> {
        let mut inner = self.inner.lock().ok()?;
        inner.get(&(key.clone(), format.to_string())).cloned()
    }

    /// Holds `rendering` as the rendering `format` of the result of `key`,
    /// unless it is larger than [`MAX_RENDERING`].
    pub fn put(&self, key: &Arc<str>, format: &str, rendering: Arc<Rendering>) {
        let bytes = rendering.body.len() + rendering.kind.len() + key.len() + format.len();
        if rendering.body.len() > MAX_RENDERING {
            return;
        }
        if let Ok(mut inner) = self.inner.lock() {
            inner.put((key.clone(), format.to_string()), rendering, bytes);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rendering(len: usize) -> Arc<Rendering> {
        Arc::new(Rendering {
            body: vec![b'x'; len].into(),
            kind: "time_history".into(),
        })
    }

    #[test]
    fn renderings_are_held_by_key_and_format_unless_large() {
        let held = Renderings::default();
        let (k1, k2): (Arc<str>, Arc<str>) = ("k1".into(), "k2".into());
        held.put(&k1, "csv", rendering(10));
        assert_eq!(held.get(&k1, "csv").map(|r| r.body.len()), Some(10));
        assert!(held.get(&k1, "svg3").is_none());
        assert!(held.get(&k2, "csv").is_none());
        held.put(&k2, "csv", rendering(MAX_RENDERING + 1));
        assert!(held.get(&k2, "csv").is_none());
    }
}
