//! CSV renderings of result documents (`?format=csv`, `topple run --format
//! csv`). Every header names its quantity and unit: `_s` seconds, `_rad`,
//! `_rad_per_s`, `_m`, `_m_per_s`, `_m_per_s2`, `_hz`, `_g` (multiples of g),
//! `_alpha_g` (multiples of α g); ratios without a suffix are dimensionless.
//! A row holds every number the result document gives for what the row is
//! about; columns added later come at the end of the row, after the ones
//! scripts already read.
//!
//! Each kind's table is in its folder (`src/kinds/<kind>/table.rs`), its
//! rows typed structs whose field names are the headers, written with the
//! toolkit of [`crate::table`]. Numbers are written to
//! [`SIGNIFICANT_DIGITS`] ([`number`]): a value the user wrote reads as
//! written (a grid value 0.7999999999999999 as 0.8).

use crate::kinds::JobResult;

pub mod stream;

#[cfg(test)]
mod every_field;
#[cfg(test)]
pub(crate) mod tests;

pub use crate::table::TableError;
pub use crate::table::number::{SIGNIFICANT_DIGITS, number};
pub use stream::SeriesRows;

/// The CSV table of a result (its kind's, [`JobResult::table`]).
pub fn to_csv(result: &JobResult) -> Result<String, TableError> {
    result.table()
}
