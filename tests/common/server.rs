//! A real `topple serve` child process, and a small blocking HTTP client over
//! std for talking to it (and to one that dies mid-request).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// A port nobody listens on right now.
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

/// A running `topple serve`; killed (SIGKILL) when dropped.
pub struct Server {
    pub child: Child,
    pub base: String,
}

/// Starts `topple serve` on `db` with `extra` arguments, its output discarded,
/// and waits until it is ready.
pub fn start(db: &str, extra: &[&str]) -> Server {
    Server::start(db, extra, None)
}

impl Server {
    /// Starts `topple serve` on `db` with `extra` arguments and waits until it
    /// is ready; its output is appended to `log` when given. A server that
    /// exits at start-up (another process took its port meanwhile) is started
    /// again on another port.
    pub fn start(db: &str, extra: &[&str], log: Option<&Path>) -> Server {
        Server::start_under(&[], db, extra, log)
    }

    /// As [`Server::start`], the binary run by `wrapper` (a program and its
    /// arguments, given the binary and its arguments after them) when not empty.
    pub fn start_under(wrapper: &[&str], db: &str, extra: &[&str], log: Option<&Path>) -> Server {
        let mut attempts = 0;
        loop {
            attempts += 1;
            match Server::try_start(wrapper, db, extra, log) {
                Ok(server) => return server,
                Err(why) if attempts < 3 => eprintln!("{why}; starting again"),
                Err(why) => panic!("{why}"),
            }
        }
    }

    fn try_start(
        wrapper: &[&str],
        db: &str,
        extra: &[&str],
        log: Option<&Path>,
    ) -> Result<Server, String> {
        let port = free_port();
        let (stdout, stderr) = match log {
            Some(path) => {
                let file = std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(path)
                    .expect("server log opens");
                let copy = file.try_clone().expect("server log handle");
                (Stdio::from(file), Stdio::from(copy))
            }
            None => (Stdio::null(), Stdio::null()),
        };
        let binary = env!("CARGO_BIN_EXE_topple");
        let mut command = match wrapper.split_first() {
            Some((program, args)) => {
                let mut c = Command::new(program);
                c.args(args).arg(binary);
                c
            }
            None => Command::new(binary),
        };
        let child = command
            .args([
                "serve",
                "--addr",
                &format!("127.0.0.1:{port}"),
                "--database",
                db,
            ])
            .args(extra)
            .stdout(stdout)
            .stderr(stderr)
            .spawn()
            .expect("server starts");
        let mut server = Server {
            child,
            base: format!("http://127.0.0.1:{port}"),
        };
        let deadline = Instant::now() + Duration::from_secs(20);
        while Instant::now() < deadline {
            if let Ok(r) = http::get_status(&format!("{}/readyz", server.base))
                && r == 200
            {
                return Ok(server);
            }
            if let Ok(Some(exit)) = server.child.try_wait() {
                return Err(format!(
                    "server at {} exited at start-up: {exit:?}",
                    server.base
                ));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        server.kill();
        panic!("server at {} never became ready", server.base);
    }

    /// SIGKILL, then reaps the process.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// SIGTERM, then waits for the exit.
    pub fn terminate(&mut self, limit: Duration) -> ExitStatus {
        let pid = self.child.id().to_string();
        let sent = Command::new("kill")
            .args(["-TERM", &pid])
            .status()
            .expect("kill runs");
        assert!(sent.success(), "kill -TERM {pid} failed");
        let deadline = Instant::now() + limit;
        loop {
            if let Some(s) = self.child.try_wait().expect("wait") {
                return s;
            }
            assert!(Instant::now() < deadline, "server did not stop");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            self.kill();
        }
    }
}

pub mod http {
    //! A tiny blocking HTTP/1.1 client over std. A response cut short (the
    //! server died while sending it) is an error, never a truncated body.
    use std::io::{Error, ErrorKind, Read, Write};
    use std::net::{TcpStream, ToSocketAddrs};
    use std::time::Duration;

    fn cut_short(what: &str) -> Error {
        Error::new(ErrorKind::UnexpectedEof, what.to_string())
    }

    fn dechunk(mut body: &[u8]) -> std::io::Result<Vec<u8>> {
        let mut out = Vec::new();
        loop {
            let line_end = body
                .windows(2)
                .position(|w| w == b"\r\n")
                .ok_or_else(|| cut_short("chunk size line"))?;
            let size_text =
                std::str::from_utf8(&body[..line_end]).map_err(|_| cut_short("chunk size text"))?;
            let size_text = size_text.split(';').next().unwrap_or("").trim();
            let size = usize::from_str_radix(size_text, 16)
                .map_err(|_| Error::new(ErrorKind::InvalidData, "chunk size"))?;
            body = &body[line_end + 2..];
            if size == 0 {
                return Ok(out);
            }
            if body.len() < size + 2 {
                return Err(cut_short("chunk"));
            }
            out.extend_from_slice(&body[..size]);
            body = &body[size + 2..];
        }
    }

    /// The value of the header `name` in the response head `headers`.
    pub fn header(headers: &str, name: &str) -> Option<String> {
        headers.lines().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.trim()
                .eq_ignore_ascii_case(name)
                .then(|| v.trim().to_string())
        })
    }

    /// Sends one request (`Connection: close`) and returns the status and body.
    pub fn request(method: &str, url: &str, body: Option<&str>) -> std::io::Result<(u16, String)> {
        request_full(method, url, body).map(|(status, _, body)| (status, body))
    }

    /// As [`request`], with the response head (status line and headers) too.
    pub fn request_full(
        method: &str,
        url: &str,
        body: Option<&str>,
    ) -> std::io::Result<(u16, String, String)> {
        let rest = url.trim_start_matches("http://");
        let (host, path) = rest
            .split_once('/')
            .map_or((rest, "/".to_string()), |(h, p)| (h, format!("/{p}")));
        let addr = host
            .to_socket_addrs()?
            .next()
            .ok_or_else(|| Error::new(ErrorKind::InvalidInput, "no address"))?;
        let mut s = TcpStream::connect_timeout(&addr, Duration::from_secs(5))?;
        s.set_read_timeout(Some(Duration::from_secs(30)))?;
        s.set_write_timeout(Some(Duration::from_secs(30)))?;
        let body = body.unwrap_or("");
        write!(
            s,
            "{method} {path} HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )?;
        let mut raw = Vec::new();
        s.read_to_end(&mut raw)?;
        let split = raw
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .ok_or_else(|| cut_short("response head"))?;
        let head = String::from_utf8_lossy(&raw[..split]).to_string();
        let payload = &raw[split + 4..];
        let status = head
            .split_whitespace()
            .nth(1)
            .and_then(|c| c.parse().ok())
            .ok_or_else(|| Error::new(ErrorKind::InvalidData, "status line"))?;
        let header = |name: &str| {
            head.lines().skip(1).find_map(|l| {
                let (k, v) = l.split_once(':')?;
                k.trim()
                    .eq_ignore_ascii_case(name)
                    .then(|| v.trim().to_ascii_lowercase())
            })
        };
        let payload = if header("transfer-encoding").is_some_and(|v| v.contains("chunked")) {
            dechunk(payload)?
        } else {
            if let Some(n) = header("content-length").and_then(|v| v.parse::<usize>().ok())
                && n != payload.len()
            {
                return Err(cut_short("body"));
            }
            payload.to_vec()
        };
        let text =
            String::from_utf8(payload).map_err(|_| Error::new(ErrorKind::InvalidData, "UTF-8"))?;
        Ok((status, head, text))
    }

    /// The status of a GET.
    pub fn get_status(url: &str) -> std::io::Result<u16> {
        request("GET", url, None).map(|r| r.0)
    }

    /// A GET's status and JSON body (`Null` when the body is not JSON).
    pub fn try_get_json(url: &str) -> std::io::Result<(u16, serde_json::Value)> {
        let (status, body) = request("GET", url, None)?;
        Ok((
            status,
            serde_json::from_str(&body).unwrap_or(serde_json::Value::Null),
        ))
    }

    /// A GET's JSON body (`Null` when the body is not JSON).
    pub fn get_json(url: &str) -> serde_json::Value {
        try_get_json(url).expect("GET").1
    }

    /// A POST's status and JSON body (`Null` when the body is not JSON).
    pub fn try_post_json(
        url: &str,
        body: &serde_json::Value,
    ) -> std::io::Result<(u16, serde_json::Value)> {
        let (status, text) = request("POST", url, Some(&body.to_string()))?;
        Ok((
            status,
            serde_json::from_str(&text).unwrap_or(serde_json::Value::Null),
        ))
    }

    /// A POST's status and JSON body (`Null` when the body is not JSON).
    pub fn post_json(url: &str, body: &serde_json::Value) -> (u16, serde_json::Value) {
        try_post_json(url, body).expect("POST")
    }
}

/// CPU time (user + system) of process `pid` so far, from `/proc`.
pub fn cpu_time(pid: u32) -> Duration {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("/proc/<pid>/stat");
    // Fields after the command name (which may hold spaces) start after ')'.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 =
        fields[11].parse::<u64>().expect("utime") + fields[12].parse::<u64>().expect("stime");
    let per_second = Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(100.0);
    Duration::from_secs_f64(ticks as f64 / per_second)
}

/// The job as `GET /v1/jobs/{id}` shows it.
pub fn status(base: &str, id: &str) -> Value {
    http::get_json(&format!("{base}/v1/jobs/{id}"))
}

/// Polls job `id` until `done` holds for it or `limit` passes; returns the
/// last view.
pub fn wait_until(base: &str, id: &str, limit: Duration, done: impl Fn(&Value) -> bool) -> Value {
    let deadline = Instant::now() + limit;
    loop {
        let job = status(base, id);
        if done(&job) || Instant::now() > deadline {
            return job;
        }
        std::thread::sleep(Duration::from_millis(25));
    }
}

/// Polls job `id` until its status is `want` or `limit` passes.
pub fn wait_status(base: &str, id: &str, want: &str, limit: Duration) -> Value {
    wait_until(base, id, limit, |job| job["status"] == want)
}

/// Every job the listing shows, following its cursor to the last page.
pub fn list_all(base: &str) -> Vec<Value> {
    let mut jobs = Vec::new();
    let mut cursor = String::new();
    loop {
        let page = http::get_json(&format!("{base}/v1/jobs?limit=500&cursor={cursor}"));
        jobs.extend(
            page["jobs"]
                .as_array()
                .expect("a page of jobs")
                .iter()
                .cloned(),
        );
        match page["next_cursor"].as_str() {
            Some(next) => cursor = next.to_string(),
            None => return jobs,
        }
    }
}

/// A fresh, empty directory of this test run under the system temp dir.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("topple-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The URL of a SQLite database in `dir`.
pub fn sqlite_url(dir: &Path) -> String {
    format!("sqlite://{}", dir.join("topple.db").display())
}

/// A fresh SQLite database URL in a directory of its own.
pub fn temp_db(name: &str) -> String {
    sqlite_url(&temp_dir(name))
}
