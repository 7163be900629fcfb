//! Reading a record file: a 200,000-sample PEER AT2 file (1,000 s at
//! dt = 0.005 s, five values a line, as the NGA database writes them) read by
//! `records::read` — header, units, every number checked, the guards and the
//! peaks — beside the obvious alternative: splitting the values on
//! whitespace and parsing each with `str::parse::<f64>` (no header, no unit,
//! no check).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use topple::records::{ReadOptions, read};

const SAMPLES: usize = 200_000;

fn at2_file() -> String {
    let mut text = format!(
        "PEER NGA STRONG MOTION DATABASE RECORD\nBench Event 2026, Bench Station, 090\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= {SAMPLES}, DT=   .0050 SEC\n"
    );
    for k in 0..SAMPLES {
        let t = k as f64 * 0.005;
        let a = 0.3 * (2.0 * std::f64::consts::PI * 1.3 * t).sin() * (-t / 300.0).exp();
        text.push_str(&format!("{a:15.7E}"));
        if k % 5 == 4 {
            text.push('\n');
        }
    }
    text
}

fn records(c: &mut Criterion) {
    let text = at2_file();
    let mut group = c.benchmark_group("record_200000_samples");
    group.throughput(Throughput::Elements(SAMPLES as u64));
    group.sample_size(30);
    group.bench_function("records::read (at2)", |b| {
        b.iter(|| {
            let r = read(black_box(&text), &ReadOptions::default()).expect("reads");
            black_box(r.acc.len())
        })
    });
    group.bench_function("split_whitespace + parse (values only)", |b| {
        b.iter(|| {
            let values: Vec<f64> = black_box(&text)
                .lines()
                .skip(4)
                .flat_map(str::split_whitespace)
                .map(|v| v.parse::<f64>().unwrap_or(f64::NAN) * 9.81)
                .collect();
            black_box(values.len())
        })
    });
    group.finish();
}

criterion_group!(benches, records);
criterion_main!(benches);
