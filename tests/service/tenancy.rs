//! Tenants on one service, against real server processes: private jobs over
//! shared computations, cancel and delete, quotas, the audit log, and fair
//! turns for a small job behind big ones — on SQLite, and on two instances
//! sharing PostgreSQL.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::client::{Tenant, tokens_file};
use crate::common::server::{Server, sqlite_url, temp_dir};
use serde_json::{Value, json};
use sqlx::Connection;

/// A client of one server acting for one tenant (or none).
#[derive(Clone)]
struct Client(Tenant);

impl Client {
    fn new(base: &str, token: Option<&str>) -> Self {
        Client(Tenant::new(base, token))
    }

    async fn send(r: reqwest::RequestBuilder) -> (u16, Value) {
        let resp = r.send().await.expect("the server answers");
        let status = resp.status().as_u16();
        let body = resp.json().await.unwrap_or(Value::Null);
        (status, body)
    }

    async fn post(&self, path: &str, spec: &Value) -> (u16, Value) {
        Self::send(self.0.request(reqwest::Method::POST, path).json(spec)).await
    }

    async fn get(&self, path: &str) -> (u16, Value) {
        Self::send(self.0.request(reqwest::Method::GET, path)).await
    }

    async fn delete(&self, path: &str) -> (u16, Value) {
        Self::send(self.0.request(reqwest::Method::DELETE, path)).await
    }

    async fn submit(&self, spec: &Value) -> Value {
        let (status, job) = self.post("/v1/jobs", spec).await;
        assert!(status == 200 || status == 202, "{status} {job}");
        job
    }

    /// The job once finished (long-polling), within `limit`.
    async fn finished(&self, id: &str, limit: Duration) -> Value {
        let deadline = Instant::now() + limit;
        loop {
            let (status, job) = self.get(&format!("/v1/jobs/{id}?wait=5")).await;
            assert_eq!(status, 200, "{job}");
            let done = matches!(
                job["status"].as_str(),
                Some("succeeded" | "failed" | "canceled")
            );
            if done || Instant::now() > deadline {
                return job;
            }
        }
    }

    /// Ids of the tenant's jobs, newest first.
    async fn listed(&self) -> Vec<String> {
        let (status, page) = self.get("/v1/jobs?limit=500").await;
        assert_eq!(status, 200, "{page}");
        page["jobs"]
            .as_array()
            .expect("jobs")
            .iter()
            .filter_map(|j| j["id"].as_str().map(str::to_string))
            .collect()
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

/// A nonlinear spectrum over `frequencies` frequencies; `p` tells specs apart.
fn spectrum(frequencies: usize, p: f64) -> Value {
    json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": p, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": frequencies},
        "a_max_alpha_g": 20,
        "tolerance": 1e-4
    })
}

async fn count(db: &str, sql: &str) -> i64 {
    if db.starts_with("sqlite:") {
        let mut conn = sqlx::SqliteConnection::connect(db).await.expect("opens");
        sqlx::query_scalar(sqlx::AssertSqlSafe(sql.to_string()))
            .fetch_one(&mut conn)
            .await
            .expect("counts")
    } else {
        let mut conn = sqlx::PgConnection::connect(db).await.expect("connects");
        sqlx::query_scalar(sqlx::AssertSqlSafe(sql.to_string()))
            .fetch_one(&mut conn)
            .await
            .expect("counts")
    }
}

/// Cross-tenant reads, lists, cancels and deletes find nothing; an identical
/// spec is computed once for both; deletes purge the result with the last job.
async fn tenants_are_private_and_share_work(db: &str, alice: &Client, bob: &Client) {
    let spec = time_history(4.0);
    let a = alice.submit(&spec).await;
    let b = bob.submit(&spec).await;
    let (ida, idb) = (a["id"].as_str().expect("id"), b["id"].as_str().expect("id"));
    assert_ne!(ida, idb);
    assert_eq!(
        (a["cached"].as_bool(), b["cached"].as_bool()),
        (Some(false), Some(true))
    );
    // Another tenant's job does not exist for Bob: 404 everywhere, never 403.
    for path in [
        format!("/v1/jobs/{ida}"),
        format!("/v1/jobs/{ida}/result"),
        format!("/v1/jobs/{ida}/result?format=csv"),
        format!("/v1/jobs/{ida}/plot.svg"),
        format!("/v1/jobs/{ida}/events"),
    ] {
        let (status, problem) = bob.get(&path).await;
        assert_eq!(status, 404, "{path}: {problem}");
        assert_eq!(problem["parameter"], "id", "{problem}");
    }
    let (status, _) = bob.delete(&format!("/v1/jobs/{ida}")).await;
    assert_eq!(status, 404);
    let (status, _) = bob
        .post(&format!("/v1/jobs/{ida}/cancel"), &json!({}))
        .await;
    assert_eq!(status, 404);
    assert_eq!(alice.listed().await, vec![ida.to_string()]);
    assert_eq!(bob.listed().await, vec![idb.to_string()]);
    let done_a = alice.finished(ida, Duration::from_secs(30)).await;
    let done_b = bob.finished(idb, Duration::from_secs(30)).await;
    assert_eq!(
        (done_a["status"].as_str(), done_b["status"].as_str()),
        (Some("succeeded"), Some("succeeded"))
    );
    let (_, ra) = alice.get(&format!("/v1/jobs/{ida}/result")).await;
    let (_, rb) = bob.get(&format!("/v1/jobs/{idb}/result")).await;
    assert_eq!(ra, rb);
    // Computed once: one computation, its one task claimed once.
    assert_eq!(count(db, "SELECT COUNT(*) FROM computations").await, 1);
    assert_eq!(
        count(db, "SELECT CAST(SUM(attempts) AS BIGINT) FROM tasks").await,
        1
    );
    // Bob deletes his: gone for him, still there for Alice.
    let (status, _) = bob.delete(&format!("/v1/jobs/{idb}")).await;
    assert_eq!(status, 204);
    assert_eq!(bob.get(&format!("/v1/jobs/{idb}")).await.0, 404);
    assert_eq!(alice.get(&format!("/v1/jobs/{ida}/result")).await.0, 200);
    // Alice deletes hers: the computation and its result go with it.
    assert_eq!(alice.delete(&format!("/v1/jobs/{ida}")).await.0, 204);
    assert_eq!(count(db, "SELECT COUNT(*) FROM computations").await, 0);
    assert_eq!(count(db, "SELECT COUNT(*) FROM results").await, 0);
}

/// Bob cancels his job over the computation Alice's job needs too: his job
/// is canceled, hers runs to success; his resubmission then finds it done.
async fn cancel_by_one_leaves_the_other_running(alice: &Client, bob: &Client) {
    let spec = spectrum(40, 2.5);
    let a = alice.submit(&spec).await;
    let b = bob.submit(&spec).await;
    let (ida, idb) = (a["id"].as_str().expect("id"), b["id"].as_str().expect("id"));
    let (status, canceled) = bob.delete(&format!("/v1/jobs/{idb}")).await;
    assert_eq!(
        (status, canceled["status"].as_str()),
        (200, Some("canceled")),
        "{canceled}"
    );
    let done = alice.finished(ida, Duration::from_secs(120)).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let (_, bobs) = bob.get(&format!("/v1/jobs/{idb}")).await;
    assert_eq!(bobs["status"], "canceled");
    let (status, again) = bob.post("/v1/jobs", &spec).await;
    assert_eq!(
        (
            status,
            again["id"].as_str(),
            again["status"].as_str(),
            again["cached"].as_bool()
        ),
        (200, Some(idb), Some("succeeded"), Some(true)),
        "{again}"
    );
}

/// A time history submitted behind three 400-frequency spectra (of blocks of
/// p = `p`, `p` + 0.1, `p` + 0.2) finishes within 2 s and before any of them.
/// Returns how long it took.
async fn small_job_is_not_stuck_behind_big_ones(big: &Client, small: &Client, p: f64) -> Duration {
    let mut spectra = Vec::new();
    for p in [p, p + 0.1, p + 0.2] {
        let job = big.submit(&spectrum(400, p)).await;
        spectra.push(job["id"].as_str().expect("id").to_string());
    }
    // Let the spectra occupy every worker first.
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let (_, first) = big.get(&format!("/v1/jobs/{}", spectra[0])).await;
        if first["progress"].as_f64().unwrap_or(0.0) > 0.0 || Instant::now() > deadline {
            break;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let asked = Instant::now();
    let (status, job) = small.post("/v1/jobs?wait=30", &time_history(3.5)).await;
    let took = asked.elapsed();
    assert_eq!(
        (status, job["status"].as_str()),
        (200, Some("succeeded")),
        "{job}"
    );
    for id in &spectra {
        let (_, s) = big.get(&format!("/v1/jobs/{id}")).await;
        assert!(
            matches!(s["status"].as_str(), Some("queued" | "running")),
            "the small job came first: {s}"
        );
        assert!(s["progress"].as_f64().unwrap_or(1.0) < 0.5, "{s}");
    }
    assert!(took < Duration::from_secs(2), "the small job took {took:?}");
    for id in &spectra {
        let (status, _) = big.delete(&format!("/v1/jobs/{id}")).await;
        assert_eq!(status, 200);
    }
    took
}

/// Audit lines (JSON logs) of the writes, with tenant, job and request id.
fn audit_lines(log: &Path) -> Vec<Value> {
    std::fs::read_to_string(log)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|v| v["target"] == "audit")
        .collect()
}

#[tokio::test]
async fn tenants_on_sqlite() {
    let dir = temp_dir("tenancy-sqlite");
    let db = sqlite_url(&dir);
    let (tokens, t) = tokens_file(&dir, &["alice", "bob"]);
    let log = dir.join("server.log");
    let server = Server::start(
        &db,
        &[
            "--tokens-file",
            tokens.to_str().expect("path"),
            "--workers",
            "2",
            "--max-queued-per-tenant",
            "3",
            "--log-json",
        ],
        Some(&log),
    );
    let alice = Client::new(&server.base, Some(&t[0]));
    let bob = Client::new(&server.base, Some(&t[1]));
    // Without a token, or with a wrong one, nothing.
    assert_eq!(Client::new(&server.base, None).get("/v1/jobs").await.0, 401);
    assert_eq!(
        Client::new(&server.base, Some("tpl_wrong"))
            .get("/v1/jobs")
            .await
            .0,
        401
    );
    tenants_are_private_and_share_work(&db, &alice, &bob).await;
    cancel_by_one_leaves_the_other_running(&alice, &bob).await;
    // The audit log: one line per write, naming tenant, job and request.
    let marked = alice
        .0
        .request(reqwest::Method::POST, "/v1/jobs")
        .header("x-request-id", "audit-me-1")
        .json(&time_history(2.0));
    let (status, job) = Client::send(marked).await;
    assert!(status == 200 || status == 202, "{job}");
    let id = job["id"].as_str().expect("id").to_string();
    tokio::time::sleep(Duration::from_millis(200)).await;
    let lines = audit_lines(&log);
    let submit = lines
        .iter()
        .find(|l| l["fields"]["request_id"] == "audit-me-1")
        .unwrap_or_else(|| panic!("no audit line of the request in {lines:?}"));
    assert_eq!(submit["fields"]["action"], "submit");
    assert_eq!(submit["fields"]["tenant"], "alice");
    assert_eq!(submit["fields"]["job_id"], id.as_str());
    for action in ["submit", "cancel", "delete"] {
        assert!(
            lines
                .iter()
                .any(|l| l["fields"]["action"] == action && l["fields"]["tenant"] == "bob"),
            "no {action} by bob in {lines:?}"
        );
    }
    // The quota: three live jobs a tenant; the fourth waits (429), others not.
    let (status, _) = alice.delete(&format!("/v1/jobs/{id}")).await;
    assert!(status == 200 || status == 204);
    let mut live = Vec::new();
    for p in [3.1, 3.2, 3.3] {
        live.push(
            alice.submit(&spectrum(400, p)).await["id"]
                .as_str()
                .expect("id")
                .to_string(),
        );
    }
    let resp = alice
        .0
        .request(reqwest::Method::POST, "/v1/jobs")
        .json(&spectrum(400, 3.4))
        .send()
        .await
        .expect("answers");
    assert_eq!(resp.status().as_u16(), 429);
    assert!(resp.headers().contains_key("retry-after"));
    let problem: Value = resp.json().await.expect("problem");
    assert_eq!(problem["limit"], "max_queued_per_tenant", "{problem}");
    small_job_at_quota_is_refused_unless_done(&alice, &bob).await;
    // Resubmitting a job one has is no new job: answered, not refused.
    assert_eq!(alice.post("/v1/jobs", &spectrum(400, 3.1)).await.0, 202);
    // Bob is not limited by Alice's jobs: his small one comes through fast.
    let (status, quick) = bob.post("/v1/jobs?wait=30", &time_history(3.0)).await;
    assert_eq!(
        (status, quick["status"].as_str()),
        (200, Some("succeeded")),
        "{quick}"
    );
    for id in &live {
        alice.delete(&format!("/v1/jobs/{id}")).await;
    }
    let took = small_job_is_not_stuck_behind_big_ones(&alice, &bob, 2.1).await;
    eprintln!("SQLite, two tenants: the small job took {took:?}");
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Alice is at her quota: a small job she waits for, computed in its
/// request, is refused as any other (its admission is read as it is stored)
/// and nothing of it is kept; once Bob has computed it, hers joins his.
async fn small_job_at_quota_is_refused_unless_done(alice: &Client, bob: &Client) {
    let ids = |page: Value| -> Vec<Value> {
        page["jobs"]
            .as_array()
            .map(|jobs| jobs.iter().map(|j| j["id"].clone()).collect())
            .unwrap_or_default()
    };
    let before = ids(alice.get("/v1/jobs?limit=100").await.1);
    let (status, problem) = alice.post("/v1/jobs?wait=10", &time_history(3.5)).await;
    assert_eq!(status, 429, "{problem}");
    assert_eq!(problem["limit"], "max_queued_per_tenant", "{problem}");
    assert_eq!(ids(alice.get("/v1/jobs?limit=100").await.1), before);
    // Bob has computed this one: Alice's job joins it, done, quota or not.
    let (status, known) = bob.post("/v1/jobs?wait=10", &time_history(3.5)).await;
    assert_eq!((status, known["status"].as_str()), (200, Some("succeeded")));
    let (status, joined) = alice.post("/v1/jobs?wait=10", &time_history(3.5)).await;
    assert_eq!(
        (
            status,
            joined["status"].as_str(),
            joined["cached"].as_bool()
        ),
        (200, Some("succeeded"), Some(true)),
        "{joined}"
    );
    alice
        .delete(&format!("/v1/jobs/{}", joined["id"].as_str().expect("id")))
        .await;
}

#[tokio::test]
async fn one_user_small_job_is_not_stuck_behind_big_ones() {
    let dir = temp_dir("tenancy-single");
    let server = Server::start(&sqlite_url(&dir), &["--workers", "2"], None);
    let user = Client::new(&server.base, None);
    let took = small_job_is_not_stuck_behind_big_ones(&user, &user, 2.1).await;
    eprintln!("SQLite, one user: the small job took {took:?}");
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

#[tokio::test]
async fn tenants_on_two_postgres_instances() {
    let Some(pg) = crate::common::pg_database("tenancy").await else {
        return;
    };
    let dir = temp_dir("tenancy-pg");
    let (tokens, t) = tokens_file(&dir, &["alice", "bob"]);
    let args = [
        "--tokens-file",
        tokens.to_str().expect("path"),
        "--workers",
        "1",
    ];
    let one = Server::start(&pg.url, &args, None);
    let two = Server::start(&pg.url, &args, None);
    // Alice on one instance, Bob on the other: ownership holds across them.
    let alice = Client::new(&one.base, Some(&t[0]));
    let bob = Client::new(&two.base, Some(&t[1]));
    tenants_are_private_and_share_work(&pg.url, &alice, &bob).await;
    let alice_there = Client::new(&two.base, Some(&t[0]));
    cancel_by_one_leaves_the_other_running(&alice_there, &bob).await;
    let took = small_job_is_not_stuck_behind_big_ones(&alice, &bob, 2.1).await;
    eprintln!("PostgreSQL, two instances, two tenants: the small job took {took:?}");
    // One tenant alone, big jobs on one instance, the small one on the other.
    let took = small_job_is_not_stuck_behind_big_ones(&alice, &alice_there, 4.1).await;
    eprintln!("PostgreSQL, two instances, one tenant: the small job took {took:?}");
    drop(one);
    drop(two);
    pg.drop_now().await;
    let _ = std::fs::remove_dir_all(&dir);
}

#[tokio::test]
async fn retention_deletes_finished_jobs_and_their_results() {
    let dir = temp_dir("tenancy-retention");
    let db = sqlite_url(&dir);
    // 0.00003 days: 2.6 s; looked for every second.
    let server = Server::start(&db, &["--retention-days", "0.00003"], None);
    let user = Client::new(&server.base, None);
    let (status, job) = user.post("/v1/jobs?wait=30", &time_history(4.0)).await;
    assert_eq!(
        (status, job["status"].as_str()),
        (200, Some("succeeded")),
        "{job}"
    );
    let id = job["id"].as_str().expect("id").to_string();
    assert_eq!(user.get(&format!("/v1/jobs/{id}/result")).await.0, 200);
    let deadline = Instant::now() + Duration::from_secs(15);
    while user.get(&format!("/v1/jobs/{id}")).await.0 == 200 {
        assert!(Instant::now() < deadline, "the job outlived its retention");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
    assert_eq!(user.get(&format!("/v1/jobs/{id}/result")).await.0, 404);
    assert_eq!(count(&db, "SELECT COUNT(*) FROM results").await, 0);
    assert_eq!(count(&db, "SELECT COUNT(*) FROM computations").await, 0);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}
