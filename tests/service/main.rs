//! `topple` as a process: the CLI, and real servers on SQLite and PostgreSQL
//! under crashes, restarts, a full disk, a stopped database, many connections,
//! large reads, reads from memory, several instances and several tenants. One
//! test binary (each module was one before), so the library and its
//! dependencies are linked once.

#[path = "../common/mod.rs"]
mod common;

mod cancel_cpu;
mod cli;
mod connections;
mod crash;
mod disk_full;
mod memory;
mod pg_restart;
mod reads;
mod restart;
mod scale;
mod store;
mod tenancy;
