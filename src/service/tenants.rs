//! Tenants and their tokens: the tokens file (`--tokens-file`).
//!
//! One line per token, `NAME DIGEST`, separated by whitespace: `NAME` the
//! tenant (1 to 64 letters, digits, `_`, `.`, `-`, the first a letter or
//! digit), `DIGEST` `blake3:` and the 64 lowercase hex digits of the blake3
//! hash of the token. `#` starts a comment; blank lines are ignored. A tenant
//! may have several tokens (one line each: a new token is added, clients move
//! to it, the old line is removed); a digest may appear once only.
//!
//! The file holds digests, never tokens: a token presented is hashed and
//! looked up by its digest. The file is read again when its modification
//! time (or length) changes, checked at most once a second; a version
//! that does not parse is refused and the last good one kept.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime};

use tracing::{info, warn};

/// The tenant of every request without a tokens file, and of the API token
/// (`TOPPLE_API_TOKEN`).
pub const DEFAULT_TENANT: &str = "default";

/// What a token made by `topple token` starts with.
pub const TOKEN_PREFIX: &str = "tpl_";

/// What a digest in the tokens file starts with.
pub const DIGEST_PREFIX: &str = "blake3:";

/// How often the tokens file is looked at for changes, at most.
pub const RECHECK: Duration = Duration::from_secs(1);

/// What a tenant name may be, in words.
pub const NAME_RULE: &str =
    "a tenant name is 1 to 64 letters, digits, `_`, `.` or `-`, the first a letter or digit";

/// Whether `name` may name a tenant: `^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$`.
pub fn valid_name(name: &str) -> bool {
    let bytes = name.as_bytes();
    bytes.first().is_some_and(u8::is_ascii_alphanumeric)
        && bytes.len() <= 64
        && bytes
            .iter()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.' | b'-'))
}

/// The digest of `token` as the tokens file writes it: `blake3:<64 hex>`.
pub fn digest(token: &str) -> String {
    format!("{DIGEST_PREFIX}{}", blake3::hash(token.as_bytes()).to_hex())
}

/// A digest as the tokens file writes it, or `None`.
fn parse_digest(text: &str) -> Option<blake3::Hash> {
    let hex = text.strip_prefix(DIGEST_PREFIX)?;
    if hex.len() != 64 || !hex.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f')) {
        return None;
    }
    blake3::Hash::from_hex(hex).ok()
}

/// What is wrong with one line of a tokens file. Never holds a token or a
/// digest.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {what}")]
pub struct LineError {
    /// 1-based.
    pub line: usize,
    /// What is wrong.
    pub what: String,
}

/// Why a tokens file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum TokensError {
    /// It could not be read.
    #[error("tokens file {}: cannot read it: {source}", .path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A line is malformed.
    #[error("tokens file {}, {error}", .path.display())]
    Line {
        /// The file.
        path: PathBuf,
        /// Which line and what is wrong with it.
        error: LineError,
    },
}

/// Where a token was declared: a line of the file, or the API token (line 0).
struct Entry {
    tenant: Arc<str>,
    line: usize,
}

/// The registry: token digest → tenant.
#[derive(Default)]
pub struct Tenants {
    by_digest: HashMap<blake3::Hash, Entry>,
}

impl std::fmt::Debug for Tenants {
    // Digests stay out of logs and panics.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Tenants")
            .field("tokens", &self.by_digest.len())
            .finish()
    }
}

impl Tenants {
    /// The tenants of a tokens file's text.
    pub fn parse(text: &str) -> Result<Tenants, LineError> {
        Tenants::default().with_lines(text)
    }

    /// These tenants and, as one more token of tenant `tenant`, `token` (the
    /// API token: tenant `default`). A line of the file with its digest is
    /// then an error.
    pub fn with_token(mut self, tenant: &str, token: &str) -> Tenants {
        self.by_digest.insert(
            blake3::hash(token.as_bytes()),
            Entry {
                tenant: tenant.into(),
                line: 0,
            },
        );
        self
    }

    /// These tenants and those of a tokens file's text.
    pub fn with_lines(mut self, text: &str) -> Result<Tenants, LineError> {
        // One name per tenant, however many tokens it has.
        let mut names: HashMap<String, Arc<str>> = self
            .by_digest
            .values()
            .map(|e| (e.tenant.to_string(), e.tenant.clone()))
            .collect();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let fail = |what: String| LineError { line, what };
            let content = raw.split_once('#').map_or(raw, |(before, _)| before);
            let fields: Vec<&str> = content.split_whitespace().collect();
            let (name, digest) = match fields[..] {
                [] => continue,
                [name, digest] => (name, digest),
                [_] => {
                    return Err(fail(
                        "expected a tenant name and a digest (`NAME blake3:<64 hex digits>`), found one field".into(),
                    ));
                }
                _ => {
                    return Err(fail(format!(
                        "expected a tenant name and a digest (`NAME blake3:<64 hex digits>`), found {} fields",
                        fields.len()
                    )));
                }
            };
            if !valid_name(name) {
                return Err(fail(format!(
                    "the first field is not a tenant name: {NAME_RULE}"
                )));
            }
            let Some(hash) = parse_digest(digest) else {
                let what = if digest.starts_with(TOKEN_PREFIX) {
                    "the second field is a token, not its digest: the file holds `blake3:` and the 64 hex digits of the token's blake3 hash (`topple token NAME` prints the line to add)"
                } else {
                    "the second field is not a digest: `blake3:` and 64 lowercase hex digits"
                };
                return Err(fail(what.into()));
            };
            if let Some(earlier) = self.by_digest.get(&hash) {
                return Err(fail(match earlier.line {
                    0 => format!(
                        "the same digest as TOPPLE_API_TOKEN's, a token of tenant `{}`",
                        earlier.tenant
                    ),
                    n => format!("the same digest as line {n}"),
                }));
            }
            let tenant = names
                .entry(name.to_string())
                .or_insert_with(|| name.into())
                .clone();
            self.by_digest.insert(hash, Entry { tenant, line });
        }
        Ok(self)
    }

    /// The tenant whose token `token` is.
    pub fn lookup(&self, token: &str) -> Option<&Arc<str>> {
        self.by_digest
            .get(&blake3::hash(token.as_bytes()))
            .map(|e| &e.tenant)
    }

    /// How many tokens.
    pub fn len(&self) -> usize {
        self.by_digest.len()
    }

    /// Whether there is no token at all.
    pub fn is_empty(&self) -> bool {
        self.by_digest.is_empty()
    }

    /// How many tenants.
    pub fn tenant_count(&self) -> usize {
        let mut names: Vec<&str> = self.by_digest.values().map(|e| &*e.tenant).collect();
        names.sort_unstable();
        names.dedup();
        names.len()
    }
}

/// What identifies a version of the file without reading it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    modified: SystemTime,
    len: u64,
}

fn stamp(path: &Path) -> std::io::Result<Stamp> {
    let meta = std::fs::metadata(path)?;
    Ok(Stamp {
        modified: meta.modified()?,
        len: meta.len(),
    })
}

struct Watch {
    tenants: Arc<Tenants>,
    /// The version last read (parsed or not); `None` if it could not be
    /// looked at.
    stamp: Option<Stamp>,
    checked: Instant,
}

/// A tokens file, read again when it changes.
pub struct TokensFile {
    path: PathBuf,
    /// The API token, one more token of tenant `default`.
    api_token: Option<String>,
    watch: Mutex<Watch>,
}

impl std::fmt::Debug for TokensFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TokensFile")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

impl TokensFile {
    /// Reads the file at `path`; `api_token`, if any, is one more token of
    /// tenant [`DEFAULT_TENANT`].
    pub fn open(path: &Path, api_token: Option<&str>) -> Result<TokensFile, TokensError> {
        let file = TokensFile {
            path: path.to_path_buf(),
            api_token: api_token.map(str::to_string),
            watch: Mutex::new(Watch {
                tenants: Arc::new(Tenants::default()),
                stamp: None,
                checked: Instant::now(),
            }),
        };
        let stamp = stamp(path).map_err(|source| TokensError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let tenants = file.load()?;
        if let Ok(mut w) = file.watch.lock() {
            w.tenants = Arc::new(tenants);
            w.stamp = Some(stamp);
        }
        Ok(file)
    }

    /// As [`TokensFile::open`], but a file that cannot be read or parsed is
    /// logged as an error and stands for no token but the API token, until
    /// it changes into one that parses.
    pub fn open_or_empty(path: &Path, api_token: Option<&str>) -> TokensFile {
        match TokensFile::open(path, api_token) {
            Ok(file) => file,
            Err(e) => {
                tracing::error!(error = %e, "no tenant's token is accepted until the tokens file is fixed");
                let stamp = stamp(path).ok();
                TokensFile {
                    path: path.to_path_buf(),
                    api_token: api_token.map(str::to_string),
                    watch: Mutex::new(Watch {
                        tenants: Arc::new(Tenants::default().with_api_token(api_token)),
                        stamp,
                        checked: Instant::now(),
                    }),
                }
            }
        }
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn load(&self) -> Result<Tenants, TokensError> {
        let text = std::fs::read_to_string(&self.path).map_err(|source| TokensError::Read {
            path: self.path.clone(),
            source,
        })?;
        Tenants::default()
            .with_api_token(self.api_token.as_deref())
            .with_lines(&text)
            .map_err(|error| TokensError::Line {
                path: self.path.clone(),
                error,
            })
    }

    /// The tenants now: the file is looked at again if it was not in the
    /// last [`RECHECK`].
    pub fn tenants(&self) -> Arc<Tenants> {
        self.tenants_at(Instant::now())
    }

    /// The tenant whose token `token` is.
    pub fn tenant_of(&self, token: &str) -> Option<Arc<str>> {
        self.tenants().lookup(token).cloned()
    }

    fn tenants_at(&self, now: Instant) -> Arc<Tenants> {
        let mut w = self.watch.lock().unwrap_or_else(|e| e.into_inner());
        if now.saturating_duration_since(w.checked) >= RECHECK {
            w.checked = now;
            self.reload(&mut w);
        }
        w.tenants.clone()
    }

    fn reload(&self, w: &mut Watch) {
        let path = self.path.display();
        match stamp(&self.path) {
            Err(e) => {
                if w.stamp.take().is_some() {
                    warn!(path = %path, error = %e, "cannot look at the tokens file; the tokens read before stay valid");
                }
            }
            Ok(s) if w.stamp != Some(s) => {
                w.stamp = Some(s);
                match self.load() {
                    Ok(tenants) => {
                        info!(
                            path = %path,
                            tenants = tenants.tenant_count(),
                            tokens = tenants.len(),
                            "tokens file read again"
                        );
                        w.tenants = Arc::new(tenants);
                    }
                    Err(e) => {
                        warn!(error = %e, "tokens file changed but is not valid; the tokens read before stay valid");
                    }
                }
            }
            Ok(_) => {}
        }
    }
}

impl Tenants {
    fn with_api_token(self, token: Option<&str>) -> Tenants {
        match token {
            Some(t) => self.with_token(DEFAULT_TENANT, t),
            None => self,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn token(n: u8) -> String {
        format!("{TOKEN_PREFIX}{}", format!("{n:02x}").repeat(32))
    }

    fn line(name: &str, token: &str) -> String {
        format!("{name} {}\n", digest(token))
    }

    #[test]
    fn names() {
        for ok in ["a", "A", "0", "alice", "lab-2.ops_x", &"a".repeat(64)] {
            assert!(valid_name(ok), "{ok}");
        }
        for bad in [
            "",
            "-a",
            ".a",
            "_a",
            "a b",
            "a/b",
            "é",
            &"a".repeat(65),
            "a#",
        ] {
            assert!(!valid_name(bad), "{bad}");
        }
    }

    #[test]
    fn parses_names_digests_comments_and_several_tokens_per_tenant() {
        let text = format!(
            "# tenants\n\n  alice  {}\t# laptop\nalice {}\r\n   \nbob\t{}",
            digest(&token(1)),
            digest(&token(2)),
            digest(&token(3)),
        );
        let tenants = Tenants::parse(&text).expect("parses");
        assert_eq!(tenants.len(), 3);
        assert_eq!(tenants.tenant_count(), 2);
        assert_eq!(tenants.lookup(&token(1)).map(|t| &**t), Some("alice"));
        assert_eq!(tenants.lookup(&token(2)).map(|t| &**t), Some("alice"));
        assert_eq!(tenants.lookup(&token(3)).map(|t| &**t), Some("bob"));
        assert!(tenants.lookup(&token(4)).is_none());
        assert!(tenants.lookup("").is_none());
        // Both of alice's tokens name one tenant.
        let a1 = tenants.lookup(&token(1)).cloned();
        let a2 = tenants.lookup(&token(2)).cloned();
        assert!(matches!((a1, a2), (Some(x), Some(y)) if Arc::ptr_eq(&x, &y)));
    }

    #[test]
    fn malformed_lines_are_named_by_number_without_their_secrets() {
        let good = line("alice", &token(1));
        let upper = format!(
            "bob {}",
            digest(&token(2)).to_uppercase().replace("BLAKE3", "blake3")
        );
        let cases: Vec<(String, usize, &str)> = vec![
            (format!("{good}justone\n"), 2, "one field"),
            (format!("{good}\n a b c\n"), 3, "3 fields"),
            (format!("-x {}", digest(&token(2))), 1, "tenant name"),
            (format!("{good}bob {}\n", token(2)), 2, "is a token"),
            (format!("bob sha256:{}", "0".repeat(64)), 1, "not a digest"),
            (upper, 1, "not a digest"),
            (format!("bob blake3:{}", "0".repeat(63)), 1, "not a digest"),
            (
                format!("{good}#\n{}", line("bob", &token(1))),
                3,
                "as line 1",
            ),
        ];
        for (text, at, says) in cases {
            let e = Tenants::parse(&text).expect_err(&text);
            assert_eq!(e.line, at, "{text}: {e}");
            assert!(e.to_string().contains(says), "{text}: {e}");
            assert!(!e.to_string().contains(&token(2)) && !e.to_string().contains("blake3:0"));
        }
    }

    #[test]
    fn the_api_token_is_tenant_default_and_may_not_be_repeated() {
        let tenants = Tenants::default()
            .with_token("default", "s3cret")
            .with_lines(&line("alice", &token(1)))
            .expect("parses");
        assert_eq!(tenants.lookup("s3cret").map(|t| &**t), Some("default"));
        assert_eq!(tenants.lookup(&token(1)).map(|t| &**t), Some("alice"));
        let e = Tenants::default()
            .with_token("default", "s3cret")
            .with_lines(&line("alice", "s3cret"))
            .expect_err("a repeated digest");
        assert!(e.to_string().contains("TOPPLE_API_TOKEN"), "{e}");
    }

    fn temp_file(name: &str, text: &str) -> PathBuf {
        let path = std::env::temp_dir().join(format!(
            "topple-tenants-{name}-{}-{}",
            std::process::id(),
            uuid::Uuid::now_v7()
        ));
        std::fs::write(&path, text).expect("write");
        path
    }

    /// Rewrites the file and moves its modification time on, as an editor's
    /// save would on a coarse clock.
    fn rewrite(path: &Path, text: &str, seconds_later: u64) {
        std::fs::write(path, text).expect("rewrite");
        let file = std::fs::File::options()
            .write(true)
            .open(path)
            .expect("open");
        let later = SystemTime::now() + Duration::from_secs(seconds_later);
        file.set_modified(later).expect("set mtime");
    }

    #[test]
    fn the_file_is_read_again_when_it_changes_and_a_bad_version_keeps_the_last_good_one() {
        let path = temp_file("reload", &line("alice", &token(1)));
        let file = TokensFile::open(&path, Some("s3cret")).expect("opens");
        let start = Instant::now();
        let at = |s: f64| start + Duration::from_secs_f64(s);
        let tenant = |now: Instant, t: &str| file.tenants_at(now).lookup(t).map(|n| n.to_string());
        assert_eq!(tenant(at(0.0), &token(1)).as_deref(), Some("alice"));
        assert_eq!(tenant(at(0.0), "s3cret").as_deref(), Some("default"));
        assert_eq!(tenant(at(0.0), &token(2)), None);

        // bob is added: seen at the first look after a second, not before.
        let both = format!("{}{}", line("alice", &token(1)), line("bob", &token(2)));
        rewrite(&path, &both, 1);
        assert_eq!(tenant(at(0.5), &token(2)), None);
        assert_eq!(tenant(at(1.1), &token(2)).as_deref(), Some("bob"));

        // A version that does not parse: the last good one stays.
        rewrite(&path, &format!("{both}carol\n"), 2);
        assert_eq!(tenant(at(2.2), &token(2)).as_deref(), Some("bob"));
        assert_eq!(tenant(at(2.2), "s3cret").as_deref(), Some("default"));

        // Fixed: alice's token revoked, carol added.
        rewrite(
            &path,
            &format!("{}{}", line("bob", &token(2)), line("carol", &token(3))),
            3,
        );
        assert_eq!(tenant(at(3.3), &token(1)), None);
        assert_eq!(tenant(at(3.3), &token(3)).as_deref(), Some("carol"));

        // Removed: what was read stays valid.
        std::fs::remove_file(&path).expect("remove");
        assert_eq!(tenant(at(4.4), &token(3)).as_deref(), Some("carol"));
        std::fs::write(&path, line("dave", &token(4))).expect("write again");
        assert_eq!(tenant(at(5.5), &token(4)).as_deref(), Some("dave"));
        assert_eq!(tenant(at(5.5), &token(3)), None);
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn a_file_that_does_not_parse_at_start_names_itself_and_the_line() {
        let path = temp_file("bad", &format!("{}\nbob\n", line("alice", &token(1))));
        let e = TokensFile::open(&path, None).expect_err("bad line");
        let text = e.to_string();
        assert!(text.contains(&path.display().to_string()), "{text}");
        assert!(text.contains("line 3"), "{text}");
        // Started anyway (embedded), it accepts only the API token until fixed.
        let file = TokensFile::open_or_empty(&path, Some("s3cret"));
        assert!(file.tenant_of(&token(1)).is_none());
        assert_eq!(file.tenant_of("s3cret").as_deref(), Some("default"));
        let _ = std::fs::remove_file(&path);
        let missing = TokensFile::open(&path, None).expect_err("missing");
        assert!(missing.to_string().contains("cannot read"), "{missing}");
    }
}
