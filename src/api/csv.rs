//! CSV renderings of result documents (`?format=csv`, `topple run --format
//! csv`). Every header names its quantity and unit: `_s` seconds, `_rad`,
//! `_rad_per_s`, `_m`, `_m_per_s`, `_m_per_s2`, `_hz`, `_g` (multiples of g),
//! `_alpha_g` (multiples of α g); ratios without a suffix are dimensionless.
//! A row holds every number the result document gives for what the row is
//! about; columns added later come at the end of the row, after the ones
//! scripts already read.
//!
//! Each kind's table has a file of its own, its rows typed structs whose
//! field names are the headers, written with the toolkit of `table`.
//! Numbers are written to [`SIGNIFICANT_DIGITS`] ([`number`]): a value the
//! user wrote reads as written (a grid value 0.7999999999999999 as 0.8).

use crate::jobs::names::Excitation;
use crate::kinds::JobResult;

mod forensic;
mod forensic_record;
mod fragility;
mod friction;
mod number;
mod record_spectrum;
mod spectrum;
mod stream;
mod survival;
mod table;
mod text;
mod time_history;

#[cfg(test)]
mod every_field;
#[cfg(test)]
mod tests;

pub use number::{SIGNIFICANT_DIGITS, number};
pub use stream::SeriesRows;
pub use table::TableError;

/// The CSV table of a result.
pub fn to_csv(result: &JobResult) -> Result<String, TableError> {
    let mut table = table::Table::new();
    // Every kind has a table: the match is exhaustive.
    match result {
        JobResult::TimeHistory(r) => time_history::rows(r, &mut table),
        JobResult::Spectrum(r) => spectrum::rows(r, &mut table),
        JobResult::FrictionSpectrum(r) => friction::rows(r, &mut table),
        JobResult::Forensic(r) if r.excitation == Excitation::GroundMotion => {
            forensic_record::rows(r, &mut table)
        }
        JobResult::Forensic(r) => forensic::rows(r, &mut table),
        JobResult::RecordSpectrum(r) => record_spectrum::rows(r, &mut table),
        JobResult::Survival(r) => survival::rows(r, &mut table),
        JobResult::Fragility(r) => fragility::rows(r, &mut table),
    }?;
    table.finish()
}
