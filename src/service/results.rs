//! Result documents in memory. Results never change once stored, so:
//!
//! - a bounded copy of small documents is kept (the least recently read let
//!   go first), and a popular result is read from the database once;
//! - a large document (over [`MAX_BODY`]) is held only while requests use it,
//!   and every request for it meanwhile shares that one copy;
//! - large documents held at once stay within a memory budget: a request that
//!   would exceed it waits for room, and is refused when none comes in time;
//! - at most [`LOADS`] documents are read from the database at once.

use std::collections::HashMap;
use std::future::Future;
use std::sync::{Arc, Mutex, Weak};
use std::time::Duration;

use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::time::Instant;
use uuid::Uuid;

use super::lru::Lru;

/// Documents up to this size are kept after use.
pub const MAX_BODY: usize = 512 * 1024;
/// At most this many bytes of small documents are kept.
const MAX_TOTAL: usize = 64 * 1024 * 1024;
/// Documents read from the database at once: a read holds the document two
/// or three times over (the database's copy, the driver's, the text).
pub const LOADS: usize = 1;

/// A result document (JSON text), with its share of the memory budget.
#[derive(Debug)]
pub struct Document {
    text: String,
    /// Returned to the budget when the last user lets the document go.
    _budget: Option<OwnedSemaphorePermit>,
}

impl Document {
    /// The JSON text.
    pub fn as_str(&self) -> &str {
        &self.text
    }
}

/// A shared document as bytes (a response body without a copy).
#[derive(Clone, Debug)]
pub struct SharedText(pub Arc<Document>);

impl AsRef<[u8]> for SharedText {
    fn as_ref(&self) -> &[u8] {
        self.0.text.as_bytes()
    }
}

/// A finished job's result document and its job's cache key.
#[derive(Clone, Debug)]
pub struct Cached {
    /// The job's cache key (canonical spec and engine version): results of one
    /// key are the same document, so it makes their entity tag.
    pub key: Arc<str>,
    /// The result document.
    pub body: Arc<Document>,
}

/// Why a document could not be had.
#[derive(Debug)]
pub enum LoadError<E> {
    /// Reading it failed.
    Store(E),
    /// The memory budget (or the database reads) stayed taken for the whole
    /// wait.
    Busy,
}

/// Result documents by job id.
#[derive(Debug)]
pub struct ResultCache {
    inner: Mutex<Inner>,
    /// The budget of large documents held at once, in KiB.
    budget: Arc<Semaphore>,
    /// Its size, KiB.
    budget_kib: u32,
    /// Reads from the database.
    loads: Semaphore,
}

#[derive(Debug)]
struct Inner {
    /// Small documents, within [`MAX_TOTAL`] bytes.
    small: Lru<Uuid, Cached>,
    /// Large documents, while some request holds them.
    live: HashMap<Uuid, (Arc<str>, Weak<Document>)>,
}

impl Default for ResultCache {
    fn default() -> Self {
        ResultCache::new(128 << 20)
    }
}

impl ResultCache {
    /// A cache whose large documents held at once stay within `budget` bytes
    /// (a document larger than the whole budget is held alone).
    pub fn new(budget: usize) -> Self {
        let budget_kib = u32::try_from(budget.div_ceil(1024))
            .unwrap_or(u32::MAX)
            .clamp(1, Semaphore::MAX_PERMITS as u32);
        ResultCache {
            inner: Mutex::new(Inner {
                small: Lru::new(MAX_TOTAL),
                live: HashMap::new(),
            }),
            budget: Arc::new(Semaphore::new(budget_kib as usize)),
            budget_kib,
            loads: Semaphore::new(LOADS),
        }
    }

    /// The result of `id` when it is in memory.
    pub fn get(&self, id: Uuid) -> Option<Cached> {
        let mut inner = self.inner.lock().ok()?;
        if let Some(found) = inner.small.get(&id) {
            return Some(found.clone());
        }
        let (key, weak) = inner.live.get(&id)?;
        Some(Cached {
            key: key.clone(),
            body: weak.upgrade()?,
        })
    }

    /// Keeps a copy of the result `body` of job `id` (cache key `key`) if it
    /// is small enough.
    pub fn put(&self, id: Uuid, key: &str, body: &str) {
        if body.len() <= MAX_BODY {
            self.keep(id, key, body.to_string());
        }
    }

    /// Keeps small document `text`; returns it as held.
    fn keep(&self, id: Uuid, key: &str, text: String) -> Cached {
        let found = Cached {
            key: Arc::from(key),
            body: Arc::new(Document {
                text,
                _budget: None,
            }),
        };
        let Ok(mut inner) = self.inner.lock() else {
            return found;
        };
        if let Some(there) = inner.small.get(&id) {
            return there.clone();
        }
        let bytes = found.body.text.len();
        inner.small.put(id, found.clone(), bytes);
        found
    }

    /// The result of `id` (cache key `key`): from memory, else from `fetch`
    /// (`None`: not stored), waiting at most `wait` for a turn to read and
    /// for room in the budget.
    pub async fn load<E>(
        &self,
        id: Uuid,
        key: &str,
        wait: Duration,
        fetch: impl Future<Output = Result<Option<String>, E>>,
    ) -> Result<Option<Cached>, LoadError<E>> {
        if let Some(found) = self.get(id) {
            return Ok(Some(found));
        }
        let deadline = Instant::now() + wait;
        let _turn = tokio::time::timeout_at(deadline, self.loads.acquire())
            .await
            .map_err(|_| LoadError::Busy)?
            .map_err(|_| LoadError::Busy)?;
        // Another request may have read it meanwhile.
        if let Some(found) = self.get(id) {
            return Ok(Some(found));
        }
        let Some(text) = fetch.await.map_err(LoadError::Store)? else {
            return Ok(None);
        };
        if text.len() <= MAX_BODY {
            return Ok(Some(self.keep(id, key, text)));
        }
        let kib = u32::try_from(text.len().div_ceil(1024))
            .unwrap_or(u32::MAX)
            .min(self.budget_kib);
        let permit = tokio::time::timeout_at(deadline, self.budget.clone().acquire_many_owned(kib))
            .await
            .map_err(|_| LoadError::Busy)?
            .map_err(|_| LoadError::Busy)?;
        let body = Arc::new(Document {
            text,
            _budget: Some(permit),
        });
        let key: Arc<str> = Arc::from(key);
        if let Ok(mut inner) = self.inner.lock() {
            inner.live.retain(|_, (_, w)| w.strong_count() > 0);
            inner.live.insert(id, (key.clone(), Arc::downgrade(&body)));
        }
        Ok(Some(Cached { key, body }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn large(c: char) -> String {
        std::iter::repeat_n(c, MAX_BODY + 1).collect()
    }

    async fn load(cache: &ResultCache, id: Uuid, text: String) -> Result<Cached, LoadError<()>> {
        cache
            .load(id, "k", Duration::from_millis(50), async { Ok(Some(text)) })
            .await
            .map(|c| c.expect("stored"))
    }

    #[tokio::test]
    async fn small_documents_are_kept_large_ones_shared_while_held() {
        let cache = ResultCache::new(4 << 20);
        let small = Uuid::now_v7();
        cache.put(small, "k", "{}");
        assert_eq!(cache.get(small).expect("kept").body.as_str(), "{}");
        let id = Uuid::now_v7();
        cache.put(id, "k", &large('a'));
        assert!(cache.get(id).is_none(), "a large document is not kept");
        let held = load(&cache, id, large('a')).await.expect("loaded");
        // While held, it is shared: no second read.
        let again = cache
            .load(id, "k", Duration::from_millis(50), async {
                Err::<Option<String>, _>(())
            })
            .await
            .ok()
            .flatten()
            .expect("shared");
        assert!(Arc::ptr_eq(&held.body, &again.body));
        drop((held, again));
        assert!(cache.get(id).is_none(), "let go once nobody holds it");
    }

    #[tokio::test]
    async fn large_documents_held_at_once_stay_within_the_budget() {
        // Room for three documents of just over 512 KiB.
        let cache = ResultCache::new(3 * (MAX_BODY + 1024));
        let mut held = Vec::new();
        for _ in 0..3 {
            held.push(
                load(&cache, Uuid::now_v7(), large('b'))
                    .await
                    .expect("room"),
            );
        }
        assert!(matches!(
            load(&cache, Uuid::now_v7(), large('c')).await,
            Err(LoadError::Busy)
        ));
        held.pop();
        assert!(load(&cache, Uuid::now_v7(), large('c')).await.is_ok());
        // A document larger than the whole budget is served alone.
        drop(held);
        let whole = ResultCache::new(1024);
        assert!(load(&whole, Uuid::now_v7(), large('d')).await.is_ok());
    }
}
