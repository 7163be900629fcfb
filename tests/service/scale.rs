//! Several instances on one PostgreSQL: they share jobs, tasks, the cache and
//! cancellation, and one survives the other's death.

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use sqlx::Row;
use topple::kinds::Job;
use topple::service::{AppState, ServeConfig};
use topple::spectrum::Control;
use topple::startup::Application;

struct Instance {
    base: String,
    state: AppState,
    stop: tokio::sync::oneshot::Sender<()>,
    server: tokio::task::JoinHandle<()>,
}

async fn instance(db: &str, name: &str, workers: usize) -> Instance {
    let config = ServeConfig {
        addr: "127.0.0.1:0".into(),
        database_url: db.into(),
        workers,
        instance: name.into(),
        lease: Duration::from_secs(2),
        ..Default::default()
    };
    let app = Application::build(config).await.expect("builds");
    let base = format!("http://127.0.0.1:{}", app.port());
    let state = app.state().clone();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(async move {
        app.run_until(async move {
            let _ = stopped.await;
        })
        .await
        .expect("serves");
    });
    Instance {
        base,
        state,
        stop,
        server,
    }
}

impl Instance {
    async fn shutdown(self) {
        let _ = self.stop.send(());
        let _ = tokio::time::timeout(Duration::from_secs(30), self.server).await;
    }
}

fn spectrum(frequencies: usize) -> Value {
    json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": frequencies}
    })
}

async fn post(client: &reqwest::Client, base: &str, spec: &Value) -> (u16, Value) {
    let r = client
        .post(format!("{base}/v1/jobs"))
        .json(spec)
        .send()
        .await
        .expect("POST");
    (r.status().as_u16(), r.json().await.expect("json"))
}

async fn get(client: &reqwest::Client, url: &str) -> Value {
    client
        .get(url)
        .send()
        .await
        .expect("GET")
        .json()
        .await
        .expect("json")
}

async fn wait_for(
    client: &reqwest::Client,
    base: &str,
    id: &str,
    want: &str,
    limit: Duration,
) -> Value {
    let deadline = Instant::now() + limit;
    loop {
        let job = get(client, &format!("{base}/v1/jobs/{id}")).await;
        if job["status"] == want || Instant::now() > deadline {
            return job;
        }
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
}

/// The spectrum computed in one piece, in this process.
fn offline(spec: &Value) -> Value {
    Job::from_value(spec)
        .expect("valid")
        .run(&Control::new())
        .expect("runs")["spectrum"]
        .clone()
}

async fn finishers(db: &str, id: &str) -> Vec<String> {
    let pool = sqlx::PgPool::connect(db).await.expect("connects");
    let rows = sqlx::query(
        "SELECT DISTINCT split_part(done_by, '#', 1) AS who FROM tasks WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = $1)",
    )
    .bind(id)
    .fetch_all(&pool)
    .await
    .expect("reads");
    let mut who: Vec<String> = rows.iter().filter_map(|r| r.try_get("who").ok()).collect();
    who.sort();
    pool.close().await;
    who
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_instances_share_one_spectrum_and_assemble_the_single_instance_result() {
    let Some(db) = crate::common::pg_database("share").await else {
        return;
    };
    let a = instance(&db.url, "A", 1).await;
    let b = instance(&db.url, "B", 1).await;
    let client = reqwest::Client::new();
    let spec = spectrum(40);
    let (status, job) = post(&client, &a.base, &spec).await;
    assert_eq!(status, 202, "{job}");
    let id = job["id"].as_str().expect("id").to_string();
    let done = wait_for(&client, &b.base, &id, "succeeded", Duration::from_secs(120)).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    assert_eq!(
        finishers(&db.url, &id).await,
        vec!["A", "B"],
        "both instances computed tasks"
    );
    let result = get(&client, &format!("{}/v1/jobs/{id}/result", b.base)).await;
    assert_eq!(result["spectrum"], offline(&spec));
    let tasks = Job::from_value(&spec).expect("valid").split().len();
    assert!(tasks > 1, "{tasks}");
    assert_eq!(result["numerics"]["tasks"], tasks);
    a.shutdown().await;
    b.shutdown().await;
    db.drop_now().await;
}

/// Submits `spec` to one of two instances on a new database `name`, waits
/// for it through the other, checks that the instances computed its tasks
/// (more than two) and returns its result beside the one-task result of this process,
/// and the tasks.
async fn shared_by_two(name: &str, spec: &Value) -> Option<(Value, Value, usize)> {
    let db = crate::common::pg_database(name).await?;
    let a = instance(&db.url, "A", 1).await;
    let b = instance(&db.url, "B", 1).await;
    let client = reqwest::Client::new();
    let tasks = Job::from_value(spec).expect("valid").split().len();
    assert!(tasks > 2, "{tasks}");
    let (status, job) = post(&client, &a.base, spec).await;
    assert_eq!(status, 202, "{job}");
    let id = job["id"].as_str().expect("id").to_string();
    let done = wait_for(&client, &b.base, &id, "succeeded", Duration::from_secs(300)).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    // Which instance computes which task depends on how busy the machine
    // is (on a loaded one, the instance the job came to may claim every
    // task before the other wakes): what is guaranteed is that every task
    // was computed by one of the two, and that the result assembled from
    // them is the single-instance one (below).
    let who = finishers(&db.url, &id).await;
    assert!(
        !who.is_empty() && who.iter().all(|w| w == "A" || w == "B"),
        "{who:?}"
    );
    println!("{name}: tasks computed by {who:?}");
    let result = get(&client, &format!("{}/v1/jobs/{id}/result", b.base)).await;
    let whole = Job::from_value(spec)
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
    a.shutdown().await;
    b.shutdown().await;
    db.drop_now().await;
    Some((result, whole, tasks))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_instances_share_one_fragility_campaign_and_assemble_the_single_instance_result() {
    let spec = json!({"kind": "fragility",
        "block": {"alpha": {"dist": "normal", "mean": 0.2, "sd": 0.03, "min": 0.1, "max": 0.3}, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": {"dist": "lognormal", "median": 0.8, "beta": 0.3}},
        "stripes": [0.25, 0.5], "samples": 12_000, "seed": 3});
    let Some((result, whole, tasks)) = shared_by_two("fragility", &spec).await else {
        return;
    };
    for field in ["stripes", "lognormal", "monotone", "spec"] {
        assert_eq!(result[field], whole[field], "{field}");
    }
    assert_eq!(result["numerics"]["tasks"], tasks);
    assert_eq!(result["numerics"]["simulations"], 24_000);
}

/// A forensic query on a 5-s record: two blocks seen, one overturned, one
/// standing, each scanned over the record's scale in several tasks.
fn record_forensic() -> Value {
    let acc: Vec<f64> = (0..500)
        .map(|k| {
            let t = k as f64 * 0.01;
            let a = 0.3 * (std::f64::consts::TAU * 1.5 * t).sin() * (-t / 2.0).exp();
            (a * 1e5).round() / 1e5
        })
        .collect();
    json!({"kind": "forensic",
        "observations": [
            {"name": "column", "overturned": true, "block": {"alpha": 0.15, "p": 2.0}},
            {"name": "cabinet", "overturned": false, "block": {"alpha": 0.25, "p": 2.5}}],
        "scale": {"to": 4}, "scan_step_g": 0.005,
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc}})
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_instances_share_one_record_forensic_query_and_assemble_the_single_instance_result() {
    let Some((result, whole, tasks)) = shared_by_two("forensic", &record_forensic()).await else {
        return;
    };
    for field in [
        "per_observation",
        "consistent_scale",
        "bounds",
        "record",
        "spec",
    ] {
        assert_eq!(result[field], whole[field], "{field}");
    }
    assert!(
        whole["per_observation"][0]["overturning_scale"]
            .as_array()
            .is_some_and(|s| !s.is_empty()),
        "{whole}"
    );
    assert_eq!(result["numerics"]["tasks"], tasks);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_job_submitted_to_one_instance_is_visible_cancellable_and_cached_through_another() {
    let Some(db) = crate::common::pg_database("ab").await else {
        return;
    };
    let a = instance(&db.url, "A", 2).await;
    let b = instance(&db.url, "B", 1).await;
    let client = reqwest::Client::new();
    // Visible and cancellable through B while A computes it.
    let (_, job) = post(&client, &a.base, &spectrum(200)).await;
    let id = job["id"].as_str().expect("id").to_string();
    let uuid = uuid::Uuid::parse_str(&id).expect("uuid");
    let seen = get(&client, &format!("{}/v1/jobs/{id}", b.base)).await;
    assert_eq!(seen["id"], job["id"]);
    let deadline = Instant::now() + Duration::from_secs(10);
    while !a.state.computing(uuid) {
        assert!(Instant::now() < deadline, "A never started");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    let r = client
        .delete(format!("{}/v1/jobs/{id}", b.base))
        .send()
        .await
        .expect("DELETE");
    assert_eq!(r.status().as_u16(), 200);
    let asked = Instant::now();
    while a.state.computing(uuid) || b.state.computing(uuid) {
        assert!(
            asked.elapsed() < Duration::from_secs(2),
            "A kept computing a canceled job"
        );
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    let job = get(&client, &format!("{}/v1/jobs/{id}", a.base)).await;
    assert_eq!(job["status"], "canceled");
    // Computed through A, a cache hit through B.
    let small = json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_sine", "omega_ratio": 5.0, "a_p_alpha_g": 4.0}
    });
    let r = client
        .post(format!("{}/v1/jobs?wait=20", a.base))
        .json(&small)
        .send()
        .await
        .expect("POST");
    let first: Value = r.json().await.expect("json");
    assert_eq!(first["status"], "succeeded", "{first}");
    let (status, second) = post(&client, &b.base, &small).await;
    assert_eq!(status, 200);
    assert_eq!(second["cached"], true);
    assert_eq!(second["id"], first["id"]);
    a.shutdown().await;
    b.shutdown().await;
    db.drop_now().await;
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("port")
}

fn child(db: &str, name: &str) -> (Child, String) {
    let port = free_port();
    let c = Command::new(env!("CARGO_BIN_EXE_topple"))
        .args([
            "serve",
            "--addr",
            &format!("127.0.0.1:{port}"),
            "--workers",
            "1",
            "--lease",
            "1",
            "--instance",
            name,
        ])
        .env("DATABASE_URL", db)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts");
    (c, format!("http://127.0.0.1:{port}"))
}

async fn ready(client: &reqwest::Client, base: &str) {
    let deadline = Instant::now() + Duration::from_secs(20);
    while Instant::now() < deadline {
        if let Ok(r) = client.get(format!("{base}/readyz")).send().await
            && r.status().as_u16() == 200
        {
            return;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    panic!("{base} never became ready");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn when_one_instance_is_killed_the_other_takes_over_its_tasks() {
    let Some(db) = crate::common::pg_database("kill").await else {
        return;
    };
    let client = reqwest::Client::new();
    let (mut a, a_base) = child(&db.url, "A");
    let (mut b, b_base) = child(&db.url, "B");
    ready(&client, &a_base).await;
    ready(&client, &b_base).await;
    let spec = spectrum(120);
    let (status, job) = post(&client, &a_base, &spec).await;
    assert_eq!(status, 202);
    let id = job["id"].as_str().expect("id").to_string();
    // Wait until A holds a task, then kill it without warning.
    let pool = sqlx::PgPool::connect(&db.url).await.expect("connects");
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let n: i64 = sqlx::query("SELECT COUNT(*) AS n FROM tasks WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = $1) AND lease_owner LIKE 'A#%' AND status = 'running'")
            .bind(&id)
            .fetch_one(&pool)
            .await
            .expect("reads")
            .try_get("n")
            .expect("n");
        if n > 0 {
            break;
        }
        assert!(Instant::now() < deadline, "A never claimed a task");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    a.kill().expect("SIGKILL");
    let _ = a.wait();
    let done = wait_for(&client, &b_base, &id, "succeeded", Duration::from_secs(180)).await;
    assert_eq!(done["status"], "succeeded", "{done}");
    let taken_over: i64 =
        sqlx::query("SELECT COUNT(*) AS n FROM tasks WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = $1) AND attempts > 1")
            .bind(&id)
            .fetch_one(&pool)
            .await
            .expect("reads")
            .try_get("n")
            .expect("n");
    assert!(taken_over >= 1, "B took over A's lease");
    let result = get(&client, &format!("{b_base}/v1/jobs/{id}/result")).await;
    assert_eq!(result["spectrum"], offline(&spec));
    pool.close().await;
    let _ = b.kill();
    let _ = b.wait();
    db.drop_now().await;
}
