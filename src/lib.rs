//! topple: rocking and overturning of free-standing rigid blocks under
//! earthquake pulses (Makris & Zhang 2001), as a library, a command-line tool
//! and an HTTP computation service.
//!
//! # Layout
//! - [`dynamics`]: the physics, pure and synchronous — block, excitation
//!   (pulses and recorded ground motions behind one forcing trait),
//!   equations of motion (linear and nonlinear), the closed-form linear solution,
//!   adaptive Runge–Kutta pairs with dense output, event location, impacts,
//!   chattering and rest, the exact overturning decision, base reactions.
//! - [`spectrum`]: overturning and friction-demand spectra over many
//!   simulations (rayon), with progress and cancellation.
//! - [`probability`]: the normal distribution's functions, the laws of
//!   uncertain inputs, fragility fits (lognormal by maximum likelihood) and
//!   survival under a hazard curve, in closed form where one exists.
//! - [`records`]: accelerogram files (PEER `.AT2`, CSV or whitespace
//!   columns, JSON) read into samples in m/s², pure: units converted exactly,
//!   content-addressed ids, and guards against a silent misread (time taken
//!   for acceleration, a unit off by 100 or g, an uncorrected baseline).
//! - [`kinds`]: the job kinds (time histories, spectra, friction spectra,
//!   forensic queries, record spectra, fragility, survival), each a folder
//!   (`src/kinds/<kind>/`: its spec and validation, result, run, example and
//!   `impl Kind`) and one line of the registry, from which the job enum, the
//!   kind enum, every dispatch and the API description's unions are
//!   generated; service limits, canonical cache keys, splitting into tasks,
//!   and results read back into their types ([`kinds::JobResult`]) for
//!   tables and figures.
//! - [`jobs`]: what kinds are made of, below them: the typed
//!   [`jobs::kind::Kind`] trait, spec parts (block, pulse, ground motion,
//!   contact, vertical motion, distributions) and their validation into
//!   domain types, typed names, warnings, errors, cost estimates, and the
//!   parts a scan is cut into.
//! - [`store`]: one storage trait for jobs, tasks, results and records;
//!   SQLite and PostgreSQL implementations.
//! - [`service`]: the server without its routes: the state of an instance,
//!   workers that claim tasks and compute them on the rayon pool,
//!   connections, tenants and their tokens, metrics, succeeded jobs and the
//!   renderings of results in memory, and the job logic the
//!   API calls (a submission read, resolved,
//!   validated and admitted; finished results).
//! - [`api`]: axum routes, problem+json errors (the one place errors become
//!   HTTP statuses), authentication (the tenant of every request, from its
//!   token), CSV, the OpenAPI description, the page at `/`.
//! - [`startup`]: the application: the service's state and workers behind the
//!   API's router; startup and graceful shutdown.
//! - [`plot`]: SVG figures of every result kind, drawn from typed results;
//!   [`precision`]: the
//!   work-precision study; [`numbers`]: numbers as people read them.
//!
//! Data flows one way: HTTP → spec → domain types → engine → result → store →
//! HTTP. The engine never knows it is in a service; the API does no physics;
//! the service never names the API (only [`startup`] knows both).
//! `tests/import_graph.py` (run by `.ci/run`) fails on an import circle
//! between these modules, or between the files of one.

pub mod api;
pub mod dynamics;
pub mod jobs;
pub mod kinds;
pub mod numbers;
pub mod plot;
pub mod precision;
pub mod probability;
pub mod records;
pub mod service;
pub mod spectrum;
pub mod startup;
pub mod store;
pub mod table;
