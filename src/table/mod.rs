//! The table toolkit: a CSV writer set up as every table of this module is
//! written, columns that only some tables of a kind have, and a column
//! whose name a table chooses.
//!
//! A row is a `#[derive(Serialize)]` struct whose field names are the
//! columns' headers, or a tuple of such structs, written side by side. Its
//! cells are [`Number`](crate::table::number::Number)s, [`Text`](crate::table::text::Text)s,
//! counts and flags; an `Option` cell is empty when `None`.

pub mod number;
pub mod text;

use serde::Serialize;
use serde::ser::{SerializeStruct, SerializeTuple, Serializer};

/// A table that could not be written: a row whose cells do not fit the
/// table's header, a fault of this module, never of a result's values.
#[derive(Debug, thiserror::Error)]
#[error("the CSV table could not be written: {0}")]
pub struct TableError(#[from] csv::Error);

/// A CSV table being written, row by row.
///
/// Rows end with `\n`. The writer adds no quotes: numbers never need them,
/// and text is quoted by its [`Text`](crate::table::text::Text) cell, which also
/// guards it against being read as a formula (a guarded cell is quoted
/// whatever it holds, a choice the writer's quoting styles cannot make per
/// cell). Every row has as many fields as the header.
pub struct Table {
    writer: csv::Writer<Vec<u8>>,
}

impl Default for Table {
    fn default() -> Table {
        Table::new()
    }
}

impl Table {
    /// A table whose first row is preceded by its header: the row's field
    /// names.
    pub fn new() -> Table {
        Table::with_header(true)
    }

    /// Rows without a header (the rest of a table already begun).
    pub fn headless() -> Table {
        Table::with_header(false)
    }

    fn with_header(header: bool) -> Table {
        let writer = csv::WriterBuilder::new()
            .has_headers(header)
            .terminator(csv::Terminator::Any(b'\n'))
            .quote_style(csv::QuoteStyle::Never)
            .from_writer(Vec::new());
        Table { writer }
    }

    /// Writes `row`, after the header when it is the first.
    pub fn row(&mut self, row: impl Serialize) -> Result<(), TableError> {
        Ok(self.writer.serialize(row)?)
    }

    /// The bytes written so far.
    pub fn written(&mut self) -> Result<usize, TableError> {
        self.writer.flush().map_err(csv::Error::from)?;
        Ok(self.writer.get_ref().len())
    }

    /// The table's text.
    pub fn finish(self) -> Result<String, TableError> {
        let bytes = self
            .writer
            .into_inner()
            .map_err(|e| csv::Error::from(e.into_error()))?;
        String::from_utf8(bytes).map_err(|e| {
            TableError(csv::Error::from(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                e,
            )))
        })
    }
}

/// Columns that some tables of a kind have and others do not: the columns
/// of `T` when `Some`, none at all when `None`, in the header and in the
/// rows alike. A table decides once, and builds every row with its choice.
///
/// In a row, it comes after the struct of the columns every table has:
/// `(Row, Columns<Added>)`.
pub struct Columns<T>(pub Option<T>);

impl<T: Serialize> Serialize for Columns<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut columns = serializer.serialize_tuple(usize::from(self.0.is_some()))?;
        if let Some(c) = &self.0 {
            columns.serialize_element(c)?;
        }
        columns.end()
    }
}

/// One column whose name the table chooses (a fragility's first column is
/// named after its intensity measure): header `name`, cells `value`.
pub struct Named<T> {
    pub name: &'static str,
    pub value: T,
}

impl<T: Serialize> Serialize for Named<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut column = serializer.serialize_struct("Named", 1)?;
        column.serialize_field(self.name, &self.value)?;
        column.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Row {
        a: u8,
        b: Option<bool>,
    }

    #[derive(Serialize)]
    struct Added {
        c: &'static str,
    }

    fn table(rows: &[(Row, Columns<Added>)]) -> String {
        let mut table = Table::new();
        for row in rows {
            table.row(row).expect("a row");
        }
        table.finish().expect("a table")
    }

    #[test]
    fn headers_come_from_the_fields_and_columns_a_table_lacks_are_left_out() {
        let added = |c| Columns(Some(Added { c }));
        assert_eq!(
            table(&[
                (Row { a: 1, b: None }, added("x")),
                (
                    Row {
                        a: 2,
                        b: Some(true)
                    },
                    added("")
                )
            ]),
            "a,b,c\n1,,x\n2,true,\n"
        );
        assert_eq!(
            table(&[(
                Row {
                    a: 1,
                    b: Some(false)
                },
                Columns(None)
            )]),
            "a,b\n1,false\n"
        );
    }

    #[test]
    fn a_named_column_and_headless_rows() {
        let mut table = Table::new();
        let row = |x| {
            (
                Named {
                    name: "pga_g",
                    value: x,
                },
                Row { a: 3, b: None },
            )
        };
        table.row(row(0.5)).expect("a row");
        assert_eq!(
            table.written().expect("a length"),
            "pga_g,a,b\n0.5,3,\n".len()
        );
        let mut rest = Table::headless();
        rest.row(row(1.5)).expect("a row");
        assert_eq!(table.finish().expect("a table"), "pga_g,a,b\n0.5,3,\n");
        assert_eq!(rest.finish().expect("a table"), "1.5,3,\n");
    }

    #[test]
    fn cells_of_numbers_options_flags_and_counts() {
        use crate::table::number::Number;
        #[derive(Serialize)]
        struct Cells {
            one: Number,
            noise: Number,
            nan: Number,
            none: Option<Number>,
            mode: Option<u8>,
            flag: Option<bool>,
            count: u64,
        }
        let mut table = Table::headless();
        table
            .row(Cells {
                one: Number(1.0),
                noise: Number(0.30000000000000004),
                nan: Number(f64::NAN),
                none: None,
                mode: Some(2),
                flag: Some(false),
                count: u64::MAX,
            })
            .expect("a row");
        assert_eq!(
            table.finish().expect("a table"),
            "1.0,0.3,,,2,false,18446744073709551615\n"
        );
    }

    #[test]
    fn a_row_that_does_not_fit_the_header_is_an_error() {
        let mut table = Table::new();
        table.row(Row { a: 1, b: None }).expect("a row");
        assert!(table.row((Row { a: 1, b: None }, 2u8)).is_err());
    }
}
