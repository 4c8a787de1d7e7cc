//! Typed columns: a table's column as one constant that carries its name, its description
//! (the manifest's text) and the kind of its values, so that the stage that writes a
//! table and the one that reads it back name, describe and type each column in one place
//! ([`crate::effects_tables`] lists the effects' tables so). The writer puts a column with
//! [`Table::put`], which takes only values of the column's kind; the reader reads a cell
//! with [`Kind::read`] of its text, which takes a file written before the column existed
//! (an absent or empty cell reads as `None`, or `""` for text).

use std::marker::PhantomData;

use crate::output::{Table, Values};

/// The kind of a column's values: what the writer hands over and what a cell reads as.
pub trait Kind {
    /// What the writer hands over, one per row.
    type Written;
    /// What a cell's text reads as.
    type Read<'a>;
    /// The table's column of `values`.
    fn values(values: Vec<Self::Written>) -> Values;
    /// The value of a cell's text (`""` when the file has no such column).
    fn read(text: &str) -> Self::Read<'_>;
}

/// A kind whose cells are numbers (for means, sums and charts): a reader may take any of
/// them as an `f64`.
pub trait Numeric: Kind {}

/// Text, written as a CSV cell shows it ([`crate::escape::csv`]); reads as itself.
pub enum Text {}
/// A float in every row; reads as `None` when the cell is not a number.
pub enum Float {}
/// A float or nothing (an empty cell, a Parquet and JSON null).
pub enum OptionalFloat {}
/// A whole number.
pub enum Integer {}
/// `true` or `false`.
pub enum Boolean {}

impl Kind for Text {
    type Written = String;
    type Read<'a> = &'a str;
    fn values(values: Vec<String>) -> Values {
        Values::Text(values)
    }
    fn read(text: &str) -> &str {
        text
    }
}

impl Kind for Float {
    type Written = f64;
    type Read<'a> = Option<f64>;
    fn values(values: Vec<f64>) -> Values {
        Values::Float(values.into_iter().map(Some).collect())
    }
    fn read(text: &str) -> Option<f64> {
        text.parse().ok()
    }
}

impl Kind for OptionalFloat {
    type Written = Option<f64>;
    type Read<'a> = Option<f64>;
    fn values(values: Vec<Option<f64>>) -> Values {
        Values::Float(values)
    }
    fn read(text: &str) -> Option<f64> {
        text.parse().ok()
    }
}

impl Kind for Integer {
    type Written = i64;
    type Read<'a> = Option<i64>;
    fn values(values: Vec<i64>) -> Values {
        Values::Integer(values)
    }
    fn read(text: &str) -> Option<i64> {
        text.parse().ok()
    }
}

impl Kind for Boolean {
    type Written = bool;
    type Read<'a> = Option<bool>;
    fn values(values: Vec<bool>) -> Values {
        Values::Boolean(values)
    }
    fn read(text: &str) -> Option<bool> {
        text.parse().ok()
    }
}

impl Numeric for Float {}
impl Numeric for OptionalFloat {}
impl Numeric for Integer {}

/// One column of a table: its name, its description and (as a type) the kind of its values.
pub struct Column<K> {
    /// The name in the CSV header and the JSON keys.
    pub name: &'static str,
    /// What the column holds, with its unit (the manifest's `columns` text).
    pub description: &'static str,
    kind: PhantomData<fn() -> K>,
}

impl<K> Clone for Column<K> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<K> Copy for Column<K> {}

impl<K> std::fmt::Debug for Column<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name)
    }
}

impl<K> Column<K> {
    /// The column `name`, described by `description`.
    pub const fn new(name: &'static str, description: &'static str) -> Self {
        Self { name, description, kind: PhantomData }
    }
}

impl<K: Kind> Column<K> {
    /// The value of this column's cell whose text is `text`.
    pub fn read(self, text: &str) -> K::Read<'_> {
        K::read(text)
    }
}

impl<K: Numeric> Column<K> {
    /// This column read as numbers, a float or nothing, as every numeric column can be
    /// (columns of different numeric kinds in one list: a chart's choice of axis).
    pub const fn numbers(self) -> Column<OptionalFloat> {
        Column::new(self.name, self.description)
    }
}

impl Table {
    /// Put `column` with `values` (one per row) after the columns put so far.
    pub fn put<K: Kind>(&mut self, column: Column<K>, values: Vec<K::Written>) -> &mut Self {
        self.push(column.name, column.description, K::values(values))
    }
}

/// The columns of one table, in the order its writer puts them: a constant each and
/// `NAMES`, every name in that order (a writer's test compares its header with it).
#[macro_export]
macro_rules! table_columns {
    ($($(#[$meta:meta])* $name:ident: $kind:ty = $value:expr;)*) => {
        $($(#[$meta])* pub const $name: $crate::columns::Column<$kind> = $value;)*
        /// Every column's name, in the order the table's writer puts them.
        pub const NAMES: &[&str] = &[$($name.name),*];
    };
}

/// A table's file names: `STEM` (without its extension: `<stem>.csv`, `.json`, `.parquet`)
/// and `CSV`.
#[macro_export]
macro_rules! table_files {
    ($stem:literal) => {
        /// The table's file name without its extension (`.csv`, `.json`, `.parquet`).
        pub const STEM: &str = $stem;
        /// The table's CSV file.
        pub const CSV: &str = concat!($stem, ".csv");
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEPTH: Column<Integer> = Column::new("depth", "bounces");
    const ERROR: Column<OptionalFloat> = Column::new("error", "mean |e|");
    const NAME: Column<Text> = Column::new("name", "what it is");

    #[test]
    fn a_column_is_written_and_read_back_as_its_kind() {
        let mut table = Table::new();
        table.put(NAME, vec!["a,b".into(), "c".into()]).put(DEPTH, vec![3, -1]).put(ERROR, vec![Some(0.25), None]);
        assert_eq!(
            table.columns.iter().map(|c| (c.name.as_str(), c.description.as_str())).collect::<Vec<_>>(),
            [("name", "what it is"), ("depth", "bounces"), ("error", "mean |e|")]
        );
        let csv = String::from_utf8(table.to_csv().unwrap()).unwrap();
        assert_eq!(csv, "name,depth,error\n\"a,b\",3,0.25\nc,-1,\n");
        assert_eq!(DEPTH.read("3"), Some(3));
        assert_eq!(DEPTH.read(""), None);
        assert_eq!(ERROR.read("0.25"), Some(0.25));
        assert_eq!(ERROR.read(""), None);
        assert_eq!(NAME.read("c"), "c");
    }
}
