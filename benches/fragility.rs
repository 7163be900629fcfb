//! Fragility throughput: simulations per second per core of a Monte Carlo
//! campaign's tasks (the counting, without the fit) — the campaigns of
//! `bench/fragility_scale.py`, one chunk of 64 samples at each of their 20
//! stripes (0.1–1.5 g): the README's PBR walkthrough rock under its one-sine
//! pulse family of uncertain frequency, and under a suite of four
//! 2,000-sample records (20 s at dt = 0.01 s) — each on a one-thread pool
//! and, for comparison, on two threads.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use serde_json::{Value, json};
use std::hint::black_box;
use topple::kinds::{Job, Task};
use topple::spectrum::Control;

#[path = "../tests/common/synthetic.rs"]
mod synthetic;
use synthetic::synthetic;

/// The walkthrough's spec with `samples` per stripe, as one task of all its
/// units: what a worker runs.
fn pulse_task(samples: u32) -> (Task, u64) {
    let text = include_str!("../specs/pbr_fragility.json");
    let mut spec: Value = serde_json::from_str(text).expect("the spec reads");
    spec["stripes"] = json!({"from": 0.1, "to": 1.5, "steps": 20});
    spec["samples"] = json!(samples);
    task(spec)
}

/// The walkthrough's rock under four synthetic records of 2,000 samples.
fn record_task(samples: u32) -> (Task, u64) {
    let motions: Vec<Value> = (0..4)
        .map(|k| {
            json!({"name": format!("synthetic {k}"), "dt": 0.01, "unit": "m/s2",
                   "acc": synthetic(11 + k, 2_000, 0.01, 3.0, 0.3, 5.0)})
        })
        .collect();
    let spec = json!({"kind": "fragility",
        "block": {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.4, "max": 0.8},
                  "h": {"dist": "normal", "mean": 1.5, "sd": 0.1, "min": 1.2, "max": 1.8}},
        "ground_motions": motions,
        "stripes": {"from": 0.1, "to": 1.5, "steps": 20},
        "samples": samples, "seed": 42});
    task(spec)
}

fn task(mut spec: Value) -> (Task, u64) {
    let Job::Fragility(job) = Job::from_value(&spec).expect("valid") else {
        unreachable!("a fragility spec");
    };
    spec["part"] = json!([0, job.units()]);
    (
        Task::from_spec(&spec).expect("a task"),
        job.simulations(None),
    )
}

fn fragility(c: &mut Criterion) {
    let pools: Vec<(usize, rayon::ThreadPool)> = [1, 2]
        .into_iter()
        .map(|n| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .expect("a pool");
            (n, pool)
        })
        .collect();
    let mut g = c.benchmark_group("fragility");
    g.sample_size(10);
    for (name, (job, simulations)) in [("pulse", pulse_task(64)), ("record_2000", record_task(64))]
    {
        g.throughput(Throughput::Elements(simulations));
        for (threads, pool) in &pools {
            g.bench_function(format!("{name}/{threads}_thread"), |b| {
                b.iter(|| pool.install(|| black_box(&job).run(&Control::new())))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, fragility);
criterion_main!(benches);
