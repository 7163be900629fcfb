//! Reads of succeeded jobs from memory, against real server processes: the
//! same answers as from the database (documents, entity tags, 304s, another
//! tenant's 404), none once the job is deleted — at once on the instance
//! that deleted it, and within a bounded time on another sharing
//! PostgreSQL, also after the connection that carries the news was lost —,
//! and live reads of jobs that can still change.

use std::time::{Duration, Instant};

use serde_json::{Value, json};
use sqlx::Connection;

use crate::common::client::{Tenant, tokens_file};
use crate::common::server::{Server, sqlite_url, temp_dir};

/// An answer: its status, entity tag and body.
#[derive(Debug, PartialEq)]
struct Reply {
    status: u16,
    etag: Option<String>,
    body: String,
}

impl Reply {
    /// The problem document with what differs from request to request left
    /// out (its instance, its request id) and `id` written `ID`.
    fn refusal(&self, id: &str) -> Value {
        let mut problem: Value =
            serde_json::from_str(&self.body.replace(id, "ID")).unwrap_or(Value::Null);
        if let Some(o) = problem.as_object_mut() {
            o.remove("instance");
            o.remove("request_id");
        }
        problem
    }
}

/// A client of one server acting for one tenant.
struct Client(Tenant);

impl Client {
    fn new(base: &str, token: Option<&str>) -> Self {
        Client(Tenant::new(base, token))
    }

    async fn reply(r: reqwest::RequestBuilder) -> Result<Reply, reqwest::Error> {
        let resp = r.send().await?;
        let status = resp.status().as_u16();
        let etag = resp
            .headers()
            .get("etag")
            .and_then(|v| v.to_str().ok())
            .map(str::to_string);
        let body = resp.text().await?;
        Ok(Reply { status, etag, body })
    }

    async fn get(&self, path: &str) -> Reply {
        Self::reply(self.0.request(reqwest::Method::GET, path))
            .await
            .expect("the server answers")
    }

    async fn get_if_none_match(&self, path: &str, etag: &str) -> Reply {
        Self::reply(
            self.0
                .request(reqwest::Method::GET, path)
                .header("if-none-match", etag),
        )
        .await
        .expect("the server answers")
    }

    /// A GET given up after `limit`.
    async fn get_within(&self, path: &str, limit: Duration) -> Result<Reply, reqwest::Error> {
        Self::reply(self.0.request(reqwest::Method::GET, path).timeout(limit)).await
    }

    async fn delete(&self, path: &str) -> u16 {
        Self::reply(self.0.request(reqwest::Method::DELETE, path))
            .await
            .expect("the server answers")
            .status
    }

    async fn post(&self, path: &str, spec: &Value) -> (u16, Value) {
        let reply = Self::reply(self.0.request(reqwest::Method::POST, path).json(spec))
            .await
            .expect("the server answers");
        (
            reply.status,
            serde_json::from_str(&reply.body).unwrap_or(Value::Null),
        )
    }

    /// Submits `spec` and waits for it to succeed; its id.
    async fn succeeded(&self, spec: &Value) -> String {
        let (status, job) = self.post("/v1/jobs?wait=30", spec).await;
        assert_eq!(
            (status, job["status"].as_str()),
            (200, Some("succeeded")),
            "{job}"
        );
        job["id"].as_str().expect("id").to_string()
    }

    /// Reads of succeeded jobs so far: (from memory, from the database).
    async fn succeeded_reads(&self) -> (u64, u64) {
        let text = self.get("/metrics").await.body;
        let count = |from: &str| {
            let name = format!("topple_succeeded_reads_total{{from=\"{from}\"}} ");
            text.lines()
                .find_map(|l| l.strip_prefix(&name))
                .and_then(|n| n.trim().parse().ok())
                .unwrap_or(0)
        };
        (count("memory"), count("database"))
    }
}

fn time_history(level: f64) -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine", "omega_ratio": 5.0, "a_p_alpha_g": level},
        "formulation": "nonlinear",
        "outputs": {"series": 50}
    })
}

/// The reads of job `id`: its status, its result as JSON and CSV, its figure.
fn reads(id: &str) -> [String; 4] {
    [
        format!("/v1/jobs/{id}"),
        format!("/v1/jobs/{id}/result"),
        format!("/v1/jobs/{id}/result?format=csv"),
        format!("/v1/jobs/{id}/plot.svg"),
    ]
}

/// `client`'s reads of job `id` are refused as those of a job that never
/// existed.
async fn refused_as_if_it_never_existed(client: &Client, id: &str) {
    let never = uuid::Uuid::now_v7().to_string();
    for (path, path_never) in reads(id).iter().zip(reads(&never)) {
        let (reply, reply_never) = (client.get(path).await, client.get(&path_never).await);
        assert_eq!(reply.status, 404, "{path}: {}", reply.body);
        assert_eq!(reply.refusal(id), reply_never.refusal(&never), "{path}");
        assert_eq!(reply.refusal(id)["parameter"], "id");
    }
}

/// Polls `client`'s status read of job `id` until it is 404; how long that took.
async fn gone_within(client: &Client, id: &str, limit: Duration) -> Duration {
    let start = Instant::now();
    loop {
        let status = client.get(&format!("/v1/jobs/{id}")).await.status;
        if status == 404 {
            return start.elapsed();
        }
        assert_eq!(status, 200);
        assert!(
            start.elapsed() < limit,
            "job {id} still read {limit:?} after its deletion"
        );
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
}

#[tokio::test]
async fn succeeded_jobs_are_read_from_memory_as_from_the_database_until_deleted() {
    let dir = temp_dir("reads-sqlite");
    let (tokens, t) = tokens_file(&dir, &["alice", "bob"]);
    let server = Server::start(
        &sqlite_url(&dir),
        &[
            "--tokens-file",
            tokens.to_str().expect("path"),
            "--workers",
            "1",
        ],
        None,
    );
    let alice = Client::new(&server.base, Some(&t[0]));
    let bob = Client::new(&server.base, Some(&t[1]));
    let id = alice.succeeded(&time_history(4.0)).await;

    // Each read three times: the same document and tag, then 304 for the tag.
    let before = alice.succeeded_reads().await;
    for path in reads(&id) {
        let first = alice.get(&path).await;
        assert_eq!(first.status, 200, "{path}: {}", first.body);
        let etag = first.etag.clone().expect("an entity tag");
        assert_eq!(alice.get(&path).await, first, "{path}");
        let again = alice.get_if_none_match(&path, &etag).await;
        assert_eq!(
            (again.status, again.etag.as_deref(), again.body.as_str()),
            (304, Some(etag.as_str()), ""),
            "{path}"
        );
    }
    // One read went to the database, the eleven after it did not.
    let after = alice.succeeded_reads().await;
    assert_eq!((after.0 - before.0, after.1 - before.1), (11, 1));
    // The status document from memory is the job as the listing reads it
    // from the database.
    let status: Value = serde_json::from_str(&alice.get(&reads(&id)[0]).await.body).expect("JSON");
    let listing: Value =
        serde_json::from_str(&alice.get("/v1/jobs?include=spec").await.body).expect("JSON");
    assert_eq!(status, listing["jobs"][0]);
    assert_eq!(status["status"], "succeeded");

    // For Bob it does not exist, as before, and nothing of it is read.
    let before = alice.succeeded_reads().await;
    refused_as_if_it_never_existed(&bob, &id).await;
    assert_eq!(alice.succeeded_reads().await, before);

    // Deleted: gone at once, for every read.
    assert_eq!(alice.delete(&format!("/v1/jobs/{id}")).await, 204);
    refused_as_if_it_never_existed(&alice, &id).await;
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

#[tokio::test]
async fn jobs_that_can_still_change_are_read_live() {
    let dir = temp_dir("reads-live");
    let server = Server::start(&sqlite_url(&dir), &["--workers", "1"], None);
    let user = Client::new(&server.base, None);
    let spec = json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.2, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": 100},
        "a_max_alpha_g": 20,
        "tolerance": 1e-4
    });
    let (status, job) = user.post("/v1/jobs", &spec).await;
    assert_eq!(status, 202, "{job}");
    let id = job["id"].as_str().expect("id").to_string();
    let path = format!("/v1/jobs/{id}");
    let read = |reply: Reply| -> Value { serde_json::from_str(&reply.body).expect("JSON") };
    assert!(matches!(
        read(user.get(&path).await)["status"].as_str(),
        Some("queued" | "running")
    ));
    // Canceled, read twice, then queued again by a submission of its spec.
    assert_eq!(user.delete(&path).await, 200);
    for _ in 0..2 {
        assert_eq!(read(user.get(&path).await)["status"], "canceled");
    }
    let (status, again) = user.post("/v1/jobs", &spec).await;
    assert_eq!((status, again["id"].as_str()), (202, Some(id.as_str())));
    assert!(matches!(
        read(user.get(&path).await)["status"].as_str(),
        Some("queued" | "running" | "succeeded")
    ));
    // Queued or running, then succeeded: each read says what the job is now.
    let deadline = Instant::now() + Duration::from_secs(60);
    let done = loop {
        let job = read(user.get(&path).await);
        if job["status"] == "succeeded" || Instant::now() > deadline {
            break job;
        }
        assert!(
            matches!(job["status"].as_str(), Some("queued" | "running")),
            "{job}"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    };
    assert_eq!(
        (done["status"].as_str(), done["progress"].as_f64()),
        (Some("succeeded"), Some(1.0))
    );
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Terminates the connections that listen for notifications in `db`;
/// returns how many there were.
async fn cut_listeners(db: &str) -> u64 {
    let mut conn = sqlx::PgConnection::connect(db).await.expect("connects");
    let cut: Vec<bool> = sqlx::query_scalar(
        "SELECT pg_terminate_backend(pid) FROM pg_stat_activity \
         WHERE datname = current_database() AND pid <> pg_backend_pid() AND query ILIKE 'LISTEN%'",
    )
    .fetch_all(&mut conn)
    .await
    .expect("terminates");
    cut.len() as u64
}

/// Connections listening for notifications in `db`.
async fn listeners(db: &str) -> i64 {
    let mut conn = sqlx::PgConnection::connect(db).await.expect("connects");
    sqlx::query_scalar(
        "SELECT COUNT(*) FROM pg_stat_activity \
         WHERE datname = current_database() AND pid <> pg_backend_pid() AND query ILIKE 'LISTEN%'",
    )
    .fetch_one(&mut conn)
    .await
    .expect("counts")
}

#[tokio::test]
async fn a_deletion_on_one_instance_is_seen_on_the_other_within_a_bound() {
    let Some(pg) = crate::common::pg_database("reads").await else {
        return;
    };
    let dir = temp_dir("reads-pg");
    let (tokens, t) = tokens_file(&dir, &["alice", "bob"]);
    let args = [
        "--tokens-file",
        tokens.to_str().expect("path"),
        "--workers",
        "1",
    ];
    let one = Server::start(&pg.url, &args, None);
    let two = Server::start(&pg.url, &args, None);
    let (alice_one, alice_two) = (
        Client::new(&one.base, Some(&t[0])),
        Client::new(&two.base, Some(&t[0])),
    );
    let bob_two = Client::new(&two.base, Some(&t[1]));
    let id = alice_one.succeeded(&time_history(4.0)).await;
    // Both instances read it, and answer the same.
    let [status, result, _, _] = reads(&id);
    for path in [&status, &result] {
        let here = alice_one.get(path).await;
        assert_eq!(here.status, 200, "{path}");
        assert_eq!(alice_two.get(path).await, here, "{path}");
    }
    refused_as_if_it_never_existed(&bob_two, &id).await;

    // With the jobs locked away in the database, both still answer from
    // memory, while a read that needs the database waits for the lock.
    {
        let mut lock = sqlx::PgConnection::connect(&pg.url)
            .await
            .expect("connects");
        let mut tx = lock.begin().await.expect("begins");
        sqlx::query("LOCK TABLE jobs IN ACCESS EXCLUSIVE MODE")
            .execute(&mut *tx)
            .await
            .expect("locks");
        for client in [&alice_one, &alice_two] {
            for path in [&status, &result] {
                let reply = client
                    .get_within(path, Duration::from_secs(3))
                    .await
                    .expect("answered from memory");
                assert_eq!(reply.status, 200, "{path}");
            }
        }
        assert!(
            bob_two
                .get_within(&status, Duration::from_millis(500))
                .await
                .is_err(),
            "another tenant's read went to the database, which is locked"
        );
        tx.rollback().await.expect("unlocks");
    }

    // Deleted on one: gone there at once, and on two within a bound.
    assert_eq!(alice_one.delete(&status).await, 204);
    refused_as_if_it_never_existed(&alice_one, &id).await;
    let took = gone_within(&alice_two, &id, Duration::from_secs(2)).await;
    eprintln!("deleted on one instance: gone on the other after {took:?}");
    refused_as_if_it_never_existed(&alice_two, &id).await;

    // The connections that carry the news are lost and listen again; a
    // deletion after that is seen as before.
    let id = alice_one.succeeded(&time_history(4.5)).await;
    assert_eq!(cut_listeners(&pg.url).await, 2);
    let start = Instant::now();
    while listeners(&pg.url).await < 2 {
        assert!(
            start.elapsed() < Duration::from_secs(15),
            "not listening again"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let path = format!("/v1/jobs/{id}");
    for _ in 0..2 {
        assert_eq!(alice_two.get(&path).await.status, 200);
    }
    assert_eq!(alice_one.delete(&path).await, 204);
    let took = gone_within(&alice_two, &id, Duration::from_secs(2)).await;
    eprintln!("after listening again: gone on the other after {took:?}");

    drop(one);
    drop(two);
    pg.drop_now().await;
    let _ = std::fs::remove_dir_all(&dir);
}
