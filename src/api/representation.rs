//! A finished job's result in the representation asked for: the stored
//! JSON, its CSV table, or its figure. Reading a stored result into its type
//! and drawing or tabulating it is CPU work, done on the blocking pool.

use std::sync::Arc;

use axum::body::{Body, Bytes};
use axum::http::{HeaderMap, HeaderValue, header};
use axum::response::{IntoResponse, Response};
use tokio::sync::OwnedSemaphorePermit;
use uuid::Uuid;

use super::csv::{SeriesRows, to_csv};
use super::problem::Problem;
use crate::kinds::JobResult;
use crate::plot::{FigureError, Window};
use crate::service::AppState;
use crate::service::finished::RESULT_WAIT;
use crate::service::renderings::Rendering;
use crate::service::results::{Document, MAX_BODY};

/// The representation a result request asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Format {
    Json,
    Csv,
    /// The figure, over a window of time or whole.
    Svg(Option<crate::plot::Window>),
}

impl Format {
    /// Its name in entity tags: a figure's names its drawing's revision and
    /// its window (each window is a representation of its own).
    pub(crate) fn name(self) -> String {
        match self {
            Format::Json => "json".into(),
            Format::Csv => CSV.into(),
            Format::Svg(None) => format!("svg{}", crate::plot::FIGURES_REVISION),
            Format::Svg(Some(w)) => {
                format!("svg{}-window-{}", crate::plot::FIGURES_REVISION, w.tag())
            }
        }
    }

    /// `?format=` first; else the first of JSON, CSV and SVG that `Accept`
    /// names (any other `Accept` gets JSON).
    pub(crate) fn negotiate(format: Option<&str>, headers: &HeaderMap) -> Result<Format, Problem> {
        match format {
            Some("json") => return Ok(Format::Json),
            Some("csv") => return Ok(Format::Csv),
            Some("svg") => return Ok(Format::Svg(None)),
            Some(other) => {
                return Err(Problem::bad_request(
                    "invalid-parameter",
                    format!("format {other:?}: expected json, csv or svg"),
                )
                .param("format"));
            }
            None => {}
        }
        let accept = headers
            .get(header::ACCEPT)
            .and_then(|v| v.to_str().ok())
            .unwrap_or("");
        for range in accept.split(',') {
            let media = range.split(';').next().unwrap_or("").trim();
            let q = range
                .split(';')
                .filter_map(|p| p.trim().strip_prefix("q="))
                .filter_map(|q| q.parse::<f64>().ok())
                .next()
                .unwrap_or(1.0);
            if q <= 0.0 {
                continue;
            }
            match media.to_ascii_lowercase().as_str() {
                "application/json" | "application/*" | "*/*" => return Ok(Format::Json),
                "text/csv" => return Ok(Format::Csv),
                "image/svg+xml" => return Ok(Format::Svg(None)),
                _ => {}
            }
        }
        Ok(Format::Json)
    }
}

/// Bytes per piece of a streamed CSV table.
const CSV_PIECE: usize = 64 * 1024;

/// A turn to parse and render a whole result document of `len` bytes
/// (figures, and tables other than a series): large documents (over
/// [`MAX_BODY`]) take turns, [`crate::service::RENDERS`] at once, as a
/// document parsed is several times its text; small ones need none.
pub(crate) async fn render_turn(
    state: &AppState,
    len: usize,
) -> Result<Option<OwnedSemaphorePermit>, Problem> {
    if len <= MAX_BODY {
        return Ok(None);
    }
    tokio::time::timeout(RESULT_WAIT, state.renders.clone().acquire_owned())
        .await
        .ok()
        .and_then(Result::ok)
        .map(Some)
        .ok_or_else(|| Problem::busy("rendering"))
}

/// The CSV table of result document `doc` of job `id` (cache key `key`).
/// The series of a document larger than [`MAX_BODY`] is streamed from the
/// stored text in pieces (its samples read as they are written, the rest of
/// the document left unread); every other table is rendered from the
/// document read whole into its type, in a rendering turn when it is large,
/// and kept in memory ([`crate::service::renderings`]).
/// Parsing and rendering are not work for the runtime: they go to the
/// blocking pool rather than the compute pool, where they would queue behind
/// running spectra.
pub(crate) async fn csv_response(
    state: &AppState,
    id: Uuid,
    key: &Arc<str>,
    doc: Arc<Document>,
) -> Result<Response, Problem> {
    if let Some(held) = state.renderings.get(key, CSV) {
        return Ok(csv_table(
            Body::from(Bytes::from_owner(held.body.clone())),
            &held.kind,
            id,
        ));
    }
    let stopped = |_| Problem::internal("CSV rendering stopped");
    // A document of up to MAX_BODY is read whole into its type (so one that
    // does not read is refused); only a larger one's series is streamed.
    let rows = if doc.as_str().len() <= MAX_BODY {
        None
    } else {
        tokio::task::spawn_blocking({
            let doc = doc.clone();
            move || SeriesRows::of(doc.as_str())
        })
        .await
        .map_err(stopped)?
    };
    Ok(match rows {
        Some(rows) => csv_table(Body::from_stream(csv_pieces(rows, doc)), "time_history", id),
        None => {
            let turn = render_turn(state, doc.as_str().len()).await?;
            let (table, kind) = tokio::task::spawn_blocking(move || {
                let _turn = turn;
                let r = read_result(doc.as_str())?;
                let table = to_csv(&r).map_err(|e| Problem::internal(e.to_string()))?;
                Ok::<_, Problem>((table, r.job_kind().name()))
            })
            .await
            .map_err(stopped)??;
            let made = Arc::new(Rendering {
                body: table.into_bytes().into(),
                kind: kind.to_string(),
            });
            state.renderings.put(key, CSV, made.clone());
            csv_table(Body::from(Bytes::from_owner(made.body.clone())), kind, id)
        }
    })
}

/// The name of the CSV representation in [`crate::service::renderings`]
/// (as in [`Format::name`]).
const CSV: &str = "csv";

/// A CSV table response of job `id`, of a result of `kind`: its file is
/// named after both.
fn csv_table(body: Body, kind: &str, id: Uuid) -> Response {
    let disposition = format!("attachment; filename=\"{kind}-{id}.csv\"");
    let mut r = ([(header::CONTENT_TYPE, "text/csv; charset=utf-8")], body).into_response();
    if let Ok(v) = HeaderValue::from_str(&disposition) {
        r.headers_mut().insert(header::CONTENT_DISPOSITION, v);
    }
    r
}

/// The pieces of a series table, each written on the blocking pool when the
/// client has taken the previous one: memory per download is one piece.
fn csv_pieces(
    rows: SeriesRows,
    doc: Arc<Document>,
) -> impl futures_util::Stream<Item = Result<Bytes, std::io::Error>> + Send + 'static {
    futures_util::stream::try_unfold(Some((rows, doc)), |left| async move {
        let Some((mut rows, doc)) = left else {
            return Ok(None);
        };
        let (piece, more, rows, doc) = tokio::task::spawn_blocking(move || {
            let mut piece = String::with_capacity(CSV_PIECE + 1024);
            let more = rows.fill(doc.as_str(), &mut piece, CSV_PIECE);
            (piece, more, rows, doc)
        })
        .await
        .map_err(std::io::Error::other)?;
        let more = more.map_err(std::io::Error::other)?;
        if piece.is_empty() && !more {
            return Ok(None);
        }
        Ok(Some((Bytes::from(piece), more.then_some((rows, doc)))))
    })
}

/// A stored result document read into the type of its kind. One that does
/// not read (a result of an engine whose documents differ) is a 409 naming
/// the field, never a table or figure drawn from a guess.
pub(crate) fn read_result(text: &str) -> Result<JobResult, Problem> {
    let unreadable = |e: String| {
        Problem::conflict(
            "result-unreadable",
            format!(
                "the stored result cannot be read as a result of this engine ({e}); \
                 submit its spec again to compute it anew"
            ),
        )
    };
    let value = serde_json::from_str(text).map_err(|e| unreadable(e.to_string()))?;
    JobResult::from_value(value).map_err(|e| unreadable(e.to_string()).at(e.pointer))
}

/// The figure of result document `body`. Parsing and drawing are CPU work:
/// the blocking pool, not the runtime, in a rendering turn (a large document
/// parsed is several times its text).
pub(crate) async fn figure(
    state: &AppState,
    body: Arc<Document>,
    window: Option<Window>,
) -> Result<String, Problem> {
    let turn = render_turn(state, body.as_str().len()).await?;
    tokio::task::spawn_blocking(move || {
        let _turn = turn;
        read_result(body.as_str()).map(|r| r.figure(window))
    })
    .await
    .map_err(|_| Problem::internal("figure rendering stopped"))??
    .map_err(|e| match e {
        FigureError::Window(e) => Problem::bad_request("invalid-parameter", e).param("window"),
        FigureError::Result(e) => Problem::bad_request("no-plot", e).param("id"),
    })
}
