//! The model's estimate of a job (a spec file), and for a record spectrum
//! how its sampled estimate converges with the size of the sample: the
//! simulations a sample of N brackets foresees (N = 4, 8, …), with the sample's own
//! simulations and CPU seconds. Compare with the job's reported
//! simulations (`topple run SPEC`), verification included there.
//!
//! `cargo run --release --example sampled_estimate -- SPEC [MAX_BRACKETS]`

use topple::kinds::Job;
use topple::kinds::record_spectrum::part;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: sampled_estimate SPEC [MAX_BRACKETS]")?;
    let max: u64 = args.next().map_or(Ok(256), |a| a.parse())?;
    let text = std::fs::read_to_string(&path)?;
    let value: serde_json::Value = serde_json::from_str(&text)?;
    let any = Job::from_value(&value)?;
    let size = any.size();
    println!(
        "model: {:.0} simulations, {:.1} CPU s",
        size.work, size.cpu_s
    );
    let Job::RecordSpectrum(job) = any else {
        return Ok(());
    };
    let (lines, points) = (job.p.len(), job.grid().points());
    let mut n = 4;
    while n <= max {
        let long = std::time::Duration::from_secs(3600);
        let s = part::sample(&job, 2, long, |s| s.brackets >= n / 2)?;
        let work = s.simulations(lines, points).unwrap_or(0.0);
        println!(
            "{n:>4} brackets: {work:>9.0} simulations foreseen, {:.1} CPU s; sample {} simulations, {:.2} CPU s",
            work * s.simulation_cpu_s(),
            s.stats.simulations,
            s.cpu_s
        );
        n *= 2;
    }
    Ok(())
}
