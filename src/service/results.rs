//! A bounded in-memory copy of recent result documents: results never change
//! once stored, so a popular result is read from the database once.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};

use uuid::Uuid;

/// Results up to this size are kept.
const MAX_BODY: usize = 512 * 1024;
/// At most this many bytes in all.
const MAX_TOTAL: usize = 64 * 1024 * 1024;

/// A finished job's result document and its job's cache key.
#[derive(Clone, Debug)]
pub struct Cached {
    /// The job's cache key (canonical spec and engine version): results of one
    /// key are the same document, so it makes their entity tag.
    pub key: Arc<str>,
    /// The result document (JSON text).
    pub body: Arc<str>,
}

/// Recent results by job id, oldest evicted first.
#[derive(Debug, Default)]
pub struct ResultCache {
    inner: Mutex<Inner>,
}

#[derive(Debug, Default)]
struct Inner {
    map: HashMap<Uuid, Cached>,
    order: VecDeque<Uuid>,
    bytes: usize,
}

impl ResultCache {
    /// The cached result of `id`.
    pub fn get(&self, id: Uuid) -> Option<Cached> {
        self.inner.lock().ok()?.map.get(&id).cloned()
    }

    /// Keeps the result `body` of job `id` (cache key `key`) if it is small enough.
    pub fn put(&self, id: Uuid, key: &str, body: Arc<str>) {
        if body.len() > MAX_BODY {
            return;
        }
        let Ok(mut inner) = self.inner.lock() else {
            return;
        };
        if inner.map.contains_key(&id) {
            return;
        }
        inner.bytes += body.len();
        inner.map.insert(
            id,
            Cached {
                key: Arc::from(key),
                body,
            },
        );
        inner.order.push_back(id);
        while inner.bytes > MAX_TOTAL {
            let Some(old) = inner.order.pop_front() else {
                break;
            };
            if let Some(b) = inner.map.remove(&old) {
                inner.bytes -= b.body.len();
            }
        }
    }
}
