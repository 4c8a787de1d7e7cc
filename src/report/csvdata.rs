//! The report reads the tables the other stages wrote (CSV), so every number it shows
//! is the number in a file a user can open.

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Context, Result};

/// One record of a file being read, by column name (for `CsvTable::parse_selected`).
pub struct Record<'a> {
    record: &'a csv::StringRecord,
    index: &'a HashMap<String, usize>,
}

impl<'a> Record<'a> {
    /// The text of `column` ("" when the file has no such column).
    pub fn text(&self, column: &str) -> &'a str {
        self.index.get(column).and_then(|&i| self.record.get(i)).unwrap_or("")
    }
}

/// A CSV table held as text, with typed accessors.
#[derive(Clone, Debug, Default)]
pub struct CsvTable {
    pub headers: Vec<String>,
    pub rows: Vec<Vec<String>>,
    index: HashMap<String, usize>,
}

impl CsvTable {
    pub fn parse(bytes: &[u8]) -> Result<Self> {
        let mut reader = csv::Reader::from_reader(bytes);
        let headers: Vec<String> = reader.headers()?.iter().map(str::to_string).collect();
        let rows = reader
            .records()
            .map(|r| r.map(|r| r.iter().map(str::to_string).collect()))
            .collect::<Result<Vec<Vec<String>>, _>>()?;
        let index = headers.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        Ok(Self { headers, rows, index })
    }

    /// Only `columns` (those the file has) of the rows `keep` accepts, judged on the full
    /// record before anything is copied: a large table (errors.csv of the whole database)
    /// held in a fraction of the memory and time.
    pub fn parse_selected(bytes: &[u8], columns: &[&str], keep: &dyn Fn(&Record) -> bool) -> Result<Self> {
        let mut reader = csv::Reader::from_reader(bytes);
        let all: Vec<String> = reader.headers()?.iter().map(str::to_string).collect();
        let all_index: HashMap<String, usize> = all.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        let picked: Vec<usize> = columns.iter().filter_map(|c| all_index.get(*c).copied()).collect();
        let headers: Vec<String> = picked.iter().map(|&i| all[i].clone()).collect();
        let index = headers.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        let mut table = Self { headers, rows: Vec::new(), index };
        let mut record = csv::StringRecord::new();
        while reader.read_record(&mut record)? {
            if keep(&Record { record: &record, index: &all_index }) {
                table.rows.push(picked.iter().map(|&i| record.get(i).unwrap_or("").to_string()).collect());
            }
        }
        Ok(table)
    }

    /// Read `path`; `Ok(None)` when the file does not exist (that stage has not run).
    pub fn load(path: &Path) -> Result<Option<Self>> {
        Self::load_with(path, &|bytes| Self::parse(bytes))
    }

    /// `load` through `parse_selected`.
    pub fn load_selected(path: &Path, columns: &[&str], keep: &dyn Fn(&Record) -> bool) -> Result<Option<Self>> {
        Self::load_with(path, &|bytes| Self::parse_selected(bytes, columns, keep))
    }

    fn load_with(path: &Path, parse: &dyn Fn(&[u8]) -> Result<Self>) -> Result<Option<Self>> {
        match std::fs::read(path) {
            Ok(bytes) => Ok(Some(parse(&bytes).with_context(|| format!("reading {}", path.display()))?)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
        }
    }

    pub fn has(&self, column: &str) -> bool {
        self.index.contains_key(column)
    }

    /// The text of `column` in `row` ("" when the column is absent).
    pub fn text<'a>(&'a self, row: &'a [String], column: &str) -> &'a str {
        self.index.get(column).and_then(|&i| row.get(i)).map(String::as_str).unwrap_or("")
    }

    /// The number in `column` of `row`, `None` when empty or not a number.
    pub fn number(&self, row: &[String], column: &str) -> Option<f64> {
        self.text(row, column).parse().ok()
    }

    /// Rows whose `column` equals `value`.
    pub fn rows_where<'a>(&'a self, column: &'a str, value: &'a str) -> impl Iterator<Item = &'a Vec<String>> + 'a {
        self.rows.iter().filter(move |r| self.text(r, column) == value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_quoted_fields_and_numbers() {
        let table = CsvTable::parse(b"page,x\n\"a,b\",1.5\nc,\n").unwrap();
        assert_eq!(table.text(&table.rows[0], "page"), "a,b");
        assert_eq!(table.number(&table.rows[0], "x"), Some(1.5));
        assert_eq!(table.number(&table.rows[1], "x"), None);
        assert_eq!(table.rows_where("page", "c").count(), 1);
        let some = CsvTable::parse_selected(b"page,x,y\na,1,2\nb,3,4\n", &["y", "page", "absent"], &|r| r.text("x") == "3").unwrap();
        assert_eq!(some.headers, vec!["y", "page"]);
        assert_eq!(some.rows, vec![vec!["4".to_string(), "b".to_string()]]);
    }
}
