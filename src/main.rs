//! `topple`: command-line wiring only.

use std::io::{Read, Write};
use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand};

use topple::kinds::Job;

/// `topple --version`: the program and the engine whose numbers it gives.
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (engine ",
    topple::engine_version!(),
    ")"
);

#[derive(Parser)]
#[command(
    name = "topple",
    version = VERSION,
    about = "Rocking and overturning of free-standing rigid blocks under cycloidal pulses"
)]
struct Cli {
    /// Without a command, `topple` serves (as `topple serve`).
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(clap::Args, Clone, Debug)]
struct ServeArgs {
    /// Address to listen on.
    #[arg(long, env = "TOPPLE_ADDR", default_value = "127.0.0.1:8080")]
    addr: String,
    /// Database: sqlite://path (default ./topple.db).
    #[arg(
        long = "database",
        env = "DATABASE_URL",
        default_value = "sqlite://topple.db"
    )]
    database: String,
    /// Jobs computed at once (and compute threads); default: the number of cores.
    #[arg(long, env = "TOPPLE_WORKERS")]
    workers: Option<usize>,
    /// Largest request body, bytes.
    #[arg(long, env = "TOPPLE_MAX_BODY", default_value_t = 1 << 20)]
    max_body: usize,
    /// Largest record file uploaded to /v1/records, bytes.
    #[arg(long, env = "TOPPLE_MAX_RECORD_BYTES", default_value_t = 64 << 20)]
    max_record_bytes: usize,
    /// Most samples of an uploaded record (at most 1,000,000).
    #[arg(long, env = "TOPPLE_MAX_RECORD_SAMPLES", default_value_t = topple::jobs::spec::MAX_RECORD_SAMPLES)]
    max_record_samples: usize,
    /// Longest ?wait= honoured, seconds.
    #[arg(long, env = "TOPPLE_MAX_WAIT", default_value_t = 60.0)]
    max_wait: f64,
    /// Seconds shutdown waits for requests in flight and running jobs; then
    /// it drops the connections left and requeues the jobs left.
    #[arg(long, env = "TOPPLE_SHUTDOWN_GRACE", default_value_t = 20.0)]
    shutdown_grace: f64,
    /// Seconds a client may take to send a request's headers (from connecting,
    /// or from the first byte after an idle spell); then the connection closes.
    #[arg(long, env = "TOPPLE_HEADER_READ_TIMEOUT", default_value_t = 10.0)]
    header_read_timeout: f64,
    /// Seconds a connection may stay open with no request in flight.
    #[arg(long, env = "TOPPLE_IDLE_TIMEOUT", default_value_t = 60.0)]
    idle_timeout: f64,
    /// Seconds a client may take to send a request's body (from the end of its
    /// headers); then the request is answered 408.
    #[arg(long, env = "TOPPLE_BODY_READ_TIMEOUT", default_value_t = 30.0)]
    body_read_timeout: f64,
    /// Most connections served at once; more wait in the listen backlog.
    #[arg(long, env = "TOPPLE_MAX_CONNECTIONS", default_value_t = 1024)]
    max_connections: usize,
    /// MiB of large result documents (over 512 KiB) held in memory at once
    /// for the requests reading them; a read beyond waits for room, then
    /// answers 503.
    #[arg(long, env = "TOPPLE_RESULT_MEMORY", default_value_t = 128)]
    result_memory: usize,
    /// Seconds a claimed task stays leased without a heartbeat (then another
    /// instance may take it over).
    #[arg(long, env = "TOPPLE_LEASE", default_value_t = 10.0)]
    lease: f64,
    /// Name of this instance (lease owner); default host-pid.
    #[arg(long, env = "TOPPLE_INSTANCE")]
    instance: Option<String>,
    /// Most samples in a time history's series.
    #[arg(long, env = "TOPPLE_MAX_SERIES_POINTS", default_value_t = 200_000)]
    max_series_points: usize,
    /// Most grid points of a spectrum (frequencies × amplitude scan points).
    #[arg(long, env = "TOPPLE_MAX_GRID_POINTS", default_value_t = 4_000_000)]
    max_grid_points: usize,
    /// Most simulations one job may need (estimated before it is accepted).
    #[arg(long, env = "TOPPLE_MAX_WORK", default_value_t = 2e7)]
    max_work: f64,
    /// Most simulations × record samples one job may need (record spectra).
    #[arg(long, env = "TOPPLE_MAX_RECORD_WORK", default_value_t = 5e9)]
    max_record_work: f64,
    /// Most jobs waiting in the queue; beyond, submissions answer 429.
    #[arg(long, env = "TOPPLE_MAX_QUEUED", default_value_t = 10_000)]
    max_queued: u64,
    /// Seconds one task may compute before its job fails.
    #[arg(long, env = "TOPPLE_JOB_TIMEOUT", default_value_t = 600.0)]
    job_timeout: f64,
    /// Bearer token required by POST and DELETE (none: open).
    #[arg(long, env = "TOPPLE_API_TOKEN", hide_env_values = true)]
    api_token: Option<String>,
    /// Require the token for reads of jobs and metrics too.
    #[arg(long, env = "TOPPLE_AUTH_READS")]
    auth_reads: bool,
    /// Tenants and their tokens: one `NAME blake3:<hex digest>` line per token
    /// (`topple token NAME` prints one). With it, every request but the
    /// probes, the API description and the page needs a token, and sees only
    /// its tenant's jobs; TOPPLE_API_TOKEN is then a token of tenant
    /// `default`. Read again when it changes.
    #[arg(long, env = "TOPPLE_TOKENS_FILE")]
    tokens_file: Option<std::path::PathBuf>,
    /// Serve /metrics without a token even where reads need one.
    #[arg(long, env = "TOPPLE_METRICS_OPEN")]
    metrics_open: bool,
    /// Days a finished job is kept (fractions allowed); then it is deleted.
    /// Default: forever.
    #[arg(long, env = "TOPPLE_RETENTION_DAYS")]
    retention_days: Option<f64>,
    /// Most jobs one tenant may have queued or running; beyond, its
    /// submissions answer 429. Default: no limit but --max-queued.
    #[arg(long, env = "TOPPLE_MAX_QUEUED_PER_TENANT")]
    max_queued_per_tenant: Option<u64>,
    /// Origins allowed by CORS, comma-separated (`*`: any); none by default.
    #[arg(long, env = "TOPPLE_CORS_ORIGINS", value_delimiter = ',')]
    cors_origins: Vec<String>,
    /// Log as JSON lines instead of text.
    #[arg(long, env = "TOPPLE_LOG_JSON")]
    log_json: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Serve the HTTP API (the default command).
    Serve(Box<ServeArgs>),
    /// Print the OpenAPI description (YAML), as served at /openapi.yaml.
    Openapi,
    /// Run a job spec (a file, or - for stdin) and print the result (JSON or CSV).
    Run {
        /// Path of the job-spec JSON, or - for standard input.
        spec: String,
        /// Write a figure of the result to this SVG file.
        #[arg(long)]
        plot: Option<String>,
        /// Print the result as `json` (the default) or `csv` (a header row
        /// names quantities and units).
        #[arg(long, default_value = "json", value_parser = ["json", "csv"])]
        format: String,
    },
    /// Read a record file (PEER AT2, CSV or whitespace columns, JSON) and
    /// print it as a job spec's `ground_motion` (`dt`, `acc` in m/s², `unit`)
    /// on stdout; its metadata (one line of JSON) and warnings on stderr.
    /// With `--vertical`, a second file is the vertical component (positive
    /// up) on the same dt, printed as the `ground_motion`'s `vertical`.
    Record {
        /// The file, or - for standard input.
        file: String,
        /// The vertical component's file (positive up), read with the same
        /// options; its dt must be the horizontal one's.
        #[arg(long, value_name = "FILE")]
        vertical: Option<String>,
        /// at2 | csv | json (detected from the content when absent).
        #[arg(long)]
        format: Option<String>,
        /// g | m/s2 | cm/s2 (gal): required unless the file states it.
        #[arg(long)]
        unit: Option<String>,
        /// Sampling interval, s: required for one column without times.
        #[arg(long)]
        dt: Option<f64>,
        /// The time column: a 1-based number or a header name.
        #[arg(long)]
        time_column: Option<String>,
        /// The acceleration column: a 1-based number or a header name.
        #[arg(long)]
        acc_column: Option<String>,
        /// The record's name (default: from the file).
        #[arg(long)]
        name: Option<String>,
        /// A PGA above 5 g in the stated unit is intended.
        #[arg(long)]
        allow_large_pga: bool,
    },
    /// Make a random token for tenant NAME and print, as one line of JSON,
    /// the token and the line to append to the tokens file.
    Token {
        /// The tenant: 1 to 64 letters, digits, `_`, `.` or `-`, the first a
        /// letter or digit.
        name: String,
    },
    /// Print the work-precision table of the solvers and write its SVG diagram.
    Precision {
        /// Where to write the SVG diagram.
        #[arg(long, default_value = "precision.svg")]
        svg: String,
        /// Also rewrite the table in this Markdown file (between its `topple
        /// precision --readme` markers).
        #[arg(long)]
        readme: Option<String>,
    },
}

fn read_spec(path: &str) -> Result<String, String> {
    if path == "-" {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|e| format!("cannot read standard input: {e}"))?;
        Ok(text)
    } else {
        std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))
    }
}

/// An invalid spec: status 2 and the field.
fn invalid(e: topple::jobs::SpecError) -> (u8, String) {
    let field = if e.pointer.is_empty() {
        "/".to_string()
    } else {
        e.pointer.clone()
    };
    (2, format!("invalid spec: {field}: {}", e.message))
}

fn run(spec_path: &str, plot: Option<&str>, format: &str) -> Result<(), (u8, String)> {
    let text = read_spec(spec_path).map_err(|e| (2, e))?;
    let mut value = topple::jobs::spec::parse_json(&text).map_err(invalid)?;
    // Record files named by the spec, relative to its folder (stdin: here).
    let folder = match spec_path {
        "-" => std::path::PathBuf::from("."),
        path => std::path::Path::new(path)
            .parent()
            .map(std::path::Path::to_path_buf)
            .unwrap_or_default(),
    };
    let warnings = topple::records::embed_files(&mut value, |file| {
        std::fs::read_to_string(folder.join(file)).map_err(|e| e.to_string())
    })
    .map_err(|e| invalid(topple::jobs::SpecError::at(e.field, e.message)))?;
    for (at, w) in warnings {
        eprintln!("topple: warning: {at}: {} ({})", w.message, w.kind);
    }
    let job = Job::from_value(&value).map_err(invalid)?;
    let control = topple::spectrum::Control::new();
    let result = job
        .run(&control)
        .map_err(|e| (1, format!("computation failed: {e}")))?;
    let typed = if plot.is_some() || format == "csv" {
        let typed = topple::kinds::JobResult::from_value(result.clone())
            .map_err(|e| (1, format!("the result does not read back: {e}")))?;
        if let Some(path) = plot {
            let figure = typed
                .figure(None)
                .map_err(|e| (1, format!("cannot plot: {e}")))?;
            std::fs::write(path, figure).map_err(|e| (1, format!("cannot plot: {e}")))?;
        }
        Some(typed)
    } else {
        None
    };
    let out = match typed {
        Some(typed) if format == "csv" => topple::api::csv::to_csv(&typed)
            .map_err(|e| (1, e.to_string()))?
            .trim_end()
            .to_string(),
        _ => serde_json::to_string_pretty(&result).map_err(|e| (1, e.to_string()))?,
    };
    // A closed pipe (`topple run spec | head`) is not an error worth a panic.
    let _ = writeln!(std::io::stdout().lock(), "{out}");
    Ok(())
}

/// `topple record`: the file (and its vertical component's) as a job
/// spec's `ground_motion`.
fn record(
    file: &str,
    vertical: Option<&str>,
    options: &topple::records::OptionTexts<'_>,
) -> Result<(), (u8, String)> {
    use serde_json::{Value, json};
    let opts = options
        .read()
        .map_err(|e| (2, format!("--{}: {}", e.field.replace('_', "-"), e.message)))?;
    let horizontal = read_record_file(file, &opts)?;
    let vertical = vertical
        .map(|v| {
            // The vertical component keeps the name its file gives.
            let opts = topple::records::ReadOptions {
                name: None,
                ..opts.clone()
            };
            read_record_file(v, &opts).map(|r| (v, r))
        })
        .transpose()?;
    if let Some((path, v)) = &vertical
        && v.dt != horizontal.dt
    {
        return Err((
            2,
            format!(
                "{path}: the vertical record's dt ({} s) is not the horizontal one's ({} s, {file}): resample one of them",
                v.dt, horizontal.dt
            ),
        ));
    }
    let allow_large_pga = options.allow_large_pga;
    let mut motion = json!({"dt": horizontal.dt, "acc": horizontal.acc, "unit": "m/s2"});
    if allow_large_pga {
        motion["allow_large_pga"] = Value::Bool(true);
    }
    let mut lines = vec![(None, &horizontal)];
    if let Some((path, v)) = &vertical {
        let mut samples = json!({"acc": v.acc, "unit": "m/s2", "dt": v.dt});
        if allow_large_pga {
            samples["allow_large_pga"] = Value::Bool(true);
        }
        motion["vertical"] = samples;
        lines.push((Some(*path), v));
    }
    for (path, r) in lines {
        let meta = topple::records::RecordMeta::of(r).map_err(|e| (1, e))?;
        eprintln!(
            "{}",
            serde_json::to_string(&meta).map_err(|e| (1, e.to_string()))?
        );
        let at = path
            .map(|p| format!("{p} (vertical): "))
            .unwrap_or_default();
        for w in &r.warnings {
            eprintln!("topple: warning: {at}{} ({})", w.message, w.kind);
        }
    }
    let _ = writeln!(std::io::stdout().lock(), "{motion}");
    Ok(())
}

/// The record file at `file` (or standard input for -), read with `opts`;
/// a failure names the file and line, or the flag to give.
fn read_record_file(
    file: &str,
    opts: &topple::records::ReadOptions,
) -> Result<topple::records::RecordFile, (u8, String)> {
    let text = read_spec(file).map_err(|e| (2, e))?;
    topple::records::read(&text, opts).map_err(|e| {
        let at = match (e.field.as_str(), e.line) {
            ("body", Some(line)) => format!("{file}: line {line}"),
            ("body", None) => file.to_string(),
            (f, _) if f.starts_with('/') => format!("{file}: {f}"),
            (f, _) => format!("--{}", f.replace('_', "-")),
        };
        (2, format!("cannot read the record: {at}: {}", e.message))
    })
}

fn seconds(v: f64, name: &str) -> Result<std::time::Duration, (u8, String)> {
    match std::time::Duration::try_from_secs_f64(v) {
        Ok(d) => Ok(d),
        Err(_) => Err((
            2,
            format!("--{name} must be a non-negative number of seconds"),
        )),
    }
}

fn positive_seconds(v: f64, name: &str) -> Result<std::time::Duration, (u8, String)> {
    match seconds(v, name)? {
        d if d.is_zero() => Err((2, format!("--{name} must be a positive number of seconds"))),
        d => Ok(d),
    }
}

/// `days` as a duration: positive and finite, fractions allowed.
fn retention(days: Option<f64>) -> Result<Option<std::time::Duration>, (u8, String)> {
    let Some(days) = days else {
        return Ok(None);
    };
    match std::time::Duration::try_from_secs_f64(days * 86_400.0) {
        Ok(d) if days > 0.0 && !d.is_zero() => Ok(Some(d)),
        _ => Err((
            2,
            "--retention-days must be a positive number of days".into(),
        )),
    }
}

/// `topple token NAME`: a token from the operating system's random source,
/// and its line of the tokens file.
fn token(name: &str) -> Result<(), (u8, String)> {
    use topple::service::tenants;
    if !tenants::valid_name(name) {
        return Err((
            2,
            format!("{name:?} is not a tenant name: {}", tenants::NAME_RULE),
        ));
    }
    let mut bytes = [0u8; 32];
    getrandom::fill(&mut bytes).map_err(|e| (1, format!("no random source: {e}")))?;
    let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    let token = format!("{}{hex}", tenants::TOKEN_PREFIX);
    let line = format!("{name} {}", tenants::digest(&token));
    let out = serde_json::json!({"name": name, "token": token, "line": line});
    let _ = writeln!(std::io::stdout().lock(), "{out}");
    Ok(())
}

/// Logs to stdout, as JSON lines with `--log-json`, at the level
/// `RUST_LOG` sets (info by default).
fn init_logging(json: bool) {
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info"));
    let builder = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stdout()));
    if json {
        builder
            .json()
            .with_current_span(true)
            .with_span_list(true)
            .init();
    } else {
        builder.init();
    }
}

/// The most samples a record may have, `--max-record-samples`: 2 to
/// [`topple::jobs::spec::MAX_RECORD_SAMPLES`].
fn record_samples(n: usize) -> Result<usize, (u8, String)> {
    if (2..=topple::jobs::spec::MAX_RECORD_SAMPLES).contains(&n) {
        Ok(n)
    } else {
        Err((
            2,
            format!(
                "--max-record-samples must be 2 to {}",
                topple::jobs::spec::MAX_RECORD_SAMPLES
            ),
        ))
    }
}

/// The limits on one job's size, `--max-series-points`, `--max-grid-points`,
/// `--max-work` and `--max-record-work` (both positive).
fn limits(args: &ServeArgs) -> Result<topple::kinds::limits::Limits, (u8, String)> {
    Ok(topple::kinds::limits::Limits {
        series_points: args.max_series_points,
        grid_points: args.max_grid_points,
        work: if args.max_work > 0.0 {
            args.max_work
        } else {
            return Err((2, "--max-work must be positive".into()));
        },
        record_work: if args.max_record_work > 0.0 {
            args.max_record_work
        } else {
            return Err((2, "--max-record-work must be positive".into()));
        },
    })
}

/// The service's configuration from the command line, each option checked.
fn serve_config(args: ServeArgs) -> Result<topple::service::ServeConfig, (u8, String)> {
    if args.max_connections == 0 {
        return Err((2, "--max-connections must be at least 1".into()));
    }
    if args.result_memory == 0 {
        return Err((2, "--result-memory must be at least 1 (MiB)".into()));
    }
    if args.max_queued_per_tenant == Some(0) {
        return Err((2, "--max-queued-per-tenant must be at least 1".into()));
    }
    let mut config = topple::service::ServeConfig {
        max_record_samples: record_samples(args.max_record_samples)?,
        max_wait: seconds(args.max_wait, "max-wait")?,
        shutdown_grace: seconds(args.shutdown_grace, "shutdown-grace")?,
        lease: seconds(args.lease, "lease")?.max(std::time::Duration::from_millis(300)),
        limits: limits(&args)?,
        max_queued: args.max_queued,
        job_timeout: seconds(args.job_timeout, "job-timeout")?,
        addr: args.addr,
        database_url: args.database,
        max_body_bytes: args.max_body,
        max_record_bytes: args.max_record_bytes,
        api_token: args.api_token.filter(|t| !t.is_empty()),
        auth_reads: args.auth_reads,
        tokens_file: args.tokens_file.filter(|p| !p.as_os_str().is_empty()),
        metrics_open: args.metrics_open,
        retention: retention(args.retention_days)?,
        max_queued_per_tenant: args.max_queued_per_tenant,
        cors_origins: args
            .cors_origins
            .into_iter()
            .map(|o| o.trim().to_string())
            .filter(|o| !o.is_empty())
            .collect(),
        header_read_timeout: positive_seconds(args.header_read_timeout, "header-read-timeout")?,
        idle_timeout: positive_seconds(args.idle_timeout, "idle-timeout")?,
        body_read_timeout: positive_seconds(args.body_read_timeout, "body-read-timeout")?,
        max_connections: args.max_connections,
        result_memory: args.result_memory.saturating_mul(1 << 20),
        ..Default::default()
    };
    if let Some(name) = args.instance {
        config.instance = name;
    }
    if let Some(w) = args.workers {
        if w == 0 {
            return Err((2, "--workers must be at least 1".into()));
        }
        config.workers = w;
    }
    Ok(config)
}

fn serve(args: ServeArgs) -> Result<(), (u8, String)> {
    init_logging(args.log_json);
    let config = serve_config(args)?;
    if let Some(path) = &config.tokens_file {
        // A tokens file that does not parse stops the start; the service
        // reads it again itself, and again whenever it changes.
        let file = topple::service::tenants::TokensFile::open(path, config.api_token.as_deref())
            .map_err(|e| (2, e.to_string()))?;
        let tenants = file.tenants();
        tracing::info!(
            path = %path.display(),
            tenants = tenants.tenant_count(),
            tokens = tenants.len(),
            "tokens file read"
        );
    }
    let runtime = tokio::runtime::Runtime::new().map_err(|e| (1, e.to_string()))?;
    runtime.block_on(async move {
        let app = topple::startup::Application::build(config)
            .await
            .map_err(|e| (1, format!("cannot start: {e}")))?;
        app.run_until(topple::service::shutdown_signal())
            .await
            .map_err(|e| (1, e.to_string()))
    })
}

/// Allocations of 128 KiB and more get pages of their own, returned to the
/// system when freed. glibc otherwise raises that threshold to the largest
/// block freed so far (up to 32 MiB), after which a large result read or
/// written once stays in the heap: resident, though unused.
fn return_large_blocks() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets a tunable of the allocator; it is called
    // before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
    }
}

/// The arguments as `topple serve` takes them when the first is not a
/// command: bare `topple` (and `cargo run --release -- --addr …`) serves with
/// serve's flags.
fn with_default_command(args: Vec<std::ffi::OsString>) -> Vec<std::ffi::OsString> {
    let first = args.get(1).and_then(|a| a.to_str()).unwrap_or("");
    let top_level = ["-h", "--help", "-V", "--version", "help"];
    let command = Cli::command()
        .get_subcommands()
        .any(|c| c.get_name() == first);
    if command || top_level.contains(&first) {
        return args;
    }
    let mut out = Vec::with_capacity(args.len() + 1);
    out.extend(args.first().cloned());
    out.push("serve".into());
    out.extend(args.into_iter().skip(1));
    out
}

/// A parse error that names the environment variable a bad value came from
/// (clap names only the flag), exit status 2.
fn parse_error(e: clap::Error) -> ! {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if matches!(
        e.kind(),
        ErrorKind::ValueValidation | ErrorKind::InvalidValue
    ) && let Some(ContextValue::String(arg)) = e.get(ContextKind::InvalidArg)
    {
        let flag = arg.split_whitespace().next().unwrap_or("");
        let from_env = Cli::command()
            .find_subcommand("serve")
            .into_iter()
            .flat_map(|c| c.get_arguments().cloned().collect::<Vec<_>>())
            .find(|a| a.get_long().is_some_and(|l| format!("--{l}") == flag))
            .and_then(|a| a.get_env().map(|v| v.to_string_lossy().to_string()))
            .filter(|var| std::env::var_os(var).is_some())
            .filter(|_| !std::env::args().any(|a| a == flag || a.starts_with(&format!("{flag}="))));
        if let Some(var) = from_env {
            let _ = e.print();
            eprintln!("(the value comes from the environment variable {var})");
            std::process::exit(2);
        }
    }
    e.exit()
}

fn main() -> ExitCode {
    return_large_blocks();
    let args = with_default_command(std::env::args_os().collect());
    let cli = Cli::try_parse_from(args).unwrap_or_else(|e| parse_error(e));
    let Some(command) = cli.command else {
        // Unreachable: a missing command is `serve`.
        return ExitCode::from(2);
    };
    let outcome = match command {
        Command::Run { spec, plot, format } => run(&spec, plot.as_deref(), &format),
        Command::Precision { svg, readme } => {
            topple::precision::report(&svg, readme.as_deref(), topple::plot::precision_diagram)
                .map_err(|e| (1, e))
        }
        Command::Serve(args) => serve(*args),
        Command::Token { name } => token(&name),
        Command::Record {
            file,
            vertical,
            format,
            unit,
            dt,
            time_column,
            acc_column,
            name,
            allow_large_pga,
        } => record(
            &file,
            vertical.as_deref(),
            &topple::records::OptionTexts {
                format: format.as_deref(),
                unit: unit.as_deref(),
                dt,
                time_column: time_column.as_deref(),
                acc_column: acc_column.as_deref(),
                name: name.as_deref(),
                allow_large_pga,
            },
        ),
        Command::Openapi => {
            let _ = write!(std::io::stdout().lock(), "{}", topple::api::openapi_yaml());
            Ok(())
        }
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err((code, message)) => {
            eprintln!("topple: {}", message.replace('\n', " "));
            ExitCode::from(code)
        }
    }
}
