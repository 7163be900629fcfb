//! topple: rocking and overturning of free-standing rigid blocks under
//! earthquake pulses.
//!
//! # Layout
//! - [`dynamics`]: the physics, pure and synchronous — block, excitation,
//!   equations of motion (linear and nonlinear), the closed-form linear solution,
//!   adaptive Runge–Kutta pairs with dense output, event location, impacts and
//!   rest, the exact overturning decision, base reactions.
//! - [`jobs`]: the job-spec JSON, its validation into domain types, and the
//!   result documents.
//! - [`precision`]: the work-precision study behind `topple precision`.
//! - [`plot`]: SVG figures.

pub mod api;
pub mod dynamics;
pub mod jobs;
pub mod plot;
pub mod precision;
pub mod service;
pub mod spectrum;
pub mod store;
