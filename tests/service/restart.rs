//! A real `topple serve` process: killed with SIGKILL mid-job, restarted on the
//! same database, it loses nothing; stopped with SIGTERM, it finishes its work
//! in flight and exits cleanly.

use std::time::Duration;

use crate::common::server::{http, start, status, temp_db, wait_status, wait_until};
use serde_json::{Value, json};

fn spectrum(frequencies: usize) -> Value {
    json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": frequencies}
    })
}

fn history() -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_cosine", "omega_ratio": 3.0, "a_p_alpha_g": 2.5}
    })
}

#[test]
fn a_killed_server_loses_no_job_queued_or_running() {
    let db = temp_db("restart-kill");
    let mut first = start(&db, &["--workers", "1"]);
    let (s1, running) = http::post_json(&format!("{}/v1/jobs", first.base), &spectrum(120));
    let (s2, queued) = http::post_json(&format!("{}/v1/jobs", first.base), &history());
    assert_eq!((s1, s2), (202, 202), "{running} {queued}");
    let running_id = running["id"].as_str().expect("id").to_string();
    let queued_id = queued["id"].as_str().expect("id").to_string();
    let job = wait_status(&first.base, &running_id, "running", Duration::from_secs(10));
    assert_eq!(job["status"], "running");
    // Tasks take turns: the time history may have run between two of the
    // spectrum's tasks already.
    let other = status(&first.base, &queued_id);
    assert!(
        matches!(
            other["status"].as_str(),
            Some("queued" | "running" | "succeeded")
        ),
        "{other}"
    );
    first.kill();

    let mut second = start(&db, &["--workers", "1"]);
    for id in [&running_id, &queued_id] {
        let job = wait_status(&second.base, id, "succeeded", Duration::from_secs(60));
        assert_eq!(job["status"], "succeeded", "{job}");
    }
    let result = http::get_json(&format!("{}/v1/jobs/{running_id}/result", second.base));
    assert_eq!(result["spectrum"].as_array().map(|a| a.len()), Some(120));
    second.kill();
}

#[test]
fn sigterm_lets_the_running_job_finish_and_exits_cleanly() {
    let db = temp_db("restart-term");
    let mut server = start(&db, &["--workers", "1", "--shutdown-grace", "60"]);
    // Six frequencies on a fine amplitude grid: tasks of a good fraction of
    // a second, so that the time history submitted just before the signal
    // finds the worker busy (tasks take turns: otherwise it would run next).
    let mut long = spectrum(6);
    long["scan_step_alpha_g"] = json!(0.002);
    let (_, job) = http::post_json(&format!("{}/v1/jobs", server.base), &long);
    let id = job["id"].as_str().expect("id").to_string();
    let job = wait_until(&server.base, &id, Duration::from_secs(10), |j| {
        j["status"] == "running"
    });
    assert_eq!(job["status"], "running");
    let (_, queued) = http::post_json(&format!("{}/v1/jobs", server.base), &history());
    let queued_id = queued["id"].as_str().expect("id").to_string();
    let exit = server.terminate(Duration::from_secs(60));
    assert!(exit.success(), "{exit:?}");
    // Within the grace period the stopping server finished the job it had
    // begun — every one of its 6 tasks, not only the one in flight — and
    // started nothing new.
    let stored = |id: &str| -> String {
        tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime")
            .block_on(async {
                use sqlx::Connection;
                let mut conn = sqlx::SqliteConnection::connect(&db).await.expect("opens");
                let status: String = sqlx::query_scalar("SELECT status FROM jobs WHERE id = ?1")
                    .bind(id)
                    .fetch_one(&mut conn)
                    .await
                    .expect("the job is stored");
                status
            })
    };
    assert_eq!(stored(&id), "succeeded");
    assert_eq!(stored(&queued_id), "queued");
    let mut again = start(&db, &["--workers", "1"]);
    let result = http::get_json(&format!("{}/v1/jobs/{id}/result", again.base));
    assert_eq!(result["spectrum"].as_array().map(|a| a.len()), Some(6));
    let job = wait_status(
        &again.base,
        &queued_id,
        "succeeded",
        Duration::from_secs(60),
    );
    assert_eq!(job["status"], "succeeded", "{job}");
    again.kill();
}
