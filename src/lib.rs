//! topple (core)
pub mod dynamics;
