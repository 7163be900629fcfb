//! The physics of a rocking block: pure functions, no I/O, no async, no serde.
//!
//! Makris & Zhang (2001), *Rocking response of free-standing blocks under
//! cycloidal pulses*; equation numbers in the doc comments refer to that paper.

pub mod block;
pub mod chatter;
pub mod contact;
pub mod coulomb;
pub mod equations;
pub mod events;
pub mod exact;
pub mod excitation;
pub mod flight;
pub mod floor;
pub mod forcing;
pub mod free_rocking;
pub mod integrator;
pub mod mavroeidis_papageorgiou;
pub mod peaks;
pub mod reactions;
pub mod response;
pub mod separatrix;
pub mod simulate;
pub mod slide_rock;
pub mod sliding;
pub mod tracking;
pub mod vertical;

pub use block::Block;
pub use equations::Formulation;
pub use excitation::{Pulse, PulseShape};
pub use forcing::{Forcing, Record, RecordError};
pub use integrator::Method;
pub use response::{OverturnMode, Response};
pub use simulate::{Options, Problem, SimError, Solver, simulate};
pub use vertical::{PulsePair, RecordPair};
