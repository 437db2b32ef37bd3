//! What an analysis reports: the key numbers of its summary and its tables.
//!
//! Each analysis's report type implements [`Report`]: [`Report::summary`] is a typed,
//! serializable value (the analysis's part of the CLI's `summary.json`; the Python
//! package's `to_dict()`), and [`Report::tables`] its [`Table`]s with their column names in
//! order (the CLI writes each as `<name>.csv`; the Python package gives them as data frames).
//! The CLI and the Python package both read these, so they report the same numbers under
//! the same names.
//!
//! A table's columns hold numbers (f64), counts (whole numbers: indices, iterations,
//! records, 0/1 flags) or text. A value that does not exist (a branch lost at a speed, a
//! stability not computed) is a number that is not finite, or an empty text: an empty CSV
//! cell either way; a count always exists.

use serde::Serialize;

/// What an analysis reports.
pub trait Report {
    /// The key numbers, serialized as a JSON object.
    type Summary: Serialize;

    /// The key numbers of the result.
    fn summary(&self) -> Self::Summary;

    /// The result's tables, in the order they are written.
    fn tables(&self) -> Vec<Table>;
}

/// A table with named columns of equal length.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    name: String,
    columns: Vec<Column>,
}

/// One column of a [`Table`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Column {
    /// The column's name (the CSV header).
    pub name: String,
    /// Its values, one per row.
    pub values: Values,
}

/// The values of a [`Column`].
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Values {
    /// Numbers; one that is not finite does not exist.
    Numbers(Vec<f64>),
    /// Whole numbers (written without a decimal point, as the numbers 1.0, 2.0 are too;
    /// kept whole so that the Python package gives them as integers).
    Counts(Vec<usize>),
    /// Text; an empty text does not exist.
    Text(Vec<String>),
}

/// One cell of a [`Table`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell<'a> {
    /// A number that exists.
    Number(f64),
    /// A text that exists.
    Text(&'a str),
    /// No value.
    Missing,
}

impl Table {
    /// An empty table called `name` (its file name without `.csv`, e.g. `branch`).
    pub fn new(name: impl Into<String>) -> Table {
        Table {
            name: name.into(),
            columns: Vec::new(),
        }
    }

    /// The table's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The columns in order.
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// The column called `name`, if any.
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// The number of rows (of the first column; every column has as many).
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }

    /// Cell `row` of column `column`.
    ///
    /// # Panics
    /// When `column` or `row` is out of range.
    pub fn cell(&self, row: usize, column: usize) -> Cell<'_> {
        match &self.columns[column].values {
            Values::Numbers(v) if v[row].is_finite() => Cell::Number(v[row]),
            // Exact: a count is far below 2^53.
            Values::Counts(v) => Cell::Number(v[row] as f64),
            Values::Text(v) if !v[row].is_empty() => Cell::Text(&v[row]),
            _ => Cell::Missing,
        }
    }

    fn push(&mut self, name: impl Into<String>, values: Values) -> &mut Table {
        debug_assert!(
            self.columns.is_empty() || values.len() == self.rows(),
            "every column of a table has as many rows"
        );
        self.columns.push(Column {
            name: name.into(),
            values,
        });
        self
    }

    /// Adds a column of numbers.
    pub fn numbers(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = f64>,
    ) -> &mut Table {
        self.push(name, Values::Numbers(values.into_iter().collect()))
    }

    /// Adds a column of counts or indices (numbers that are whole).
    pub fn counts(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = usize>,
    ) -> &mut Table {
        self.push(name, Values::Counts(values.into_iter().collect()))
    }

    /// Adds a column of yes/no values written 1 and 0, as numpy and spreadsheets read a
    /// flag.
    pub fn bits(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = bool>,
    ) -> &mut Table {
        self.counts(name, values.into_iter().map(usize::from))
    }

    /// Adds a column of numbers that may not exist.
    pub fn optional(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = Option<f64>>,
    ) -> &mut Table {
        self.numbers(name, values.into_iter().map(|x| x.unwrap_or(f64::NAN)))
    }

    /// Adds a column of text.
    pub fn text<S: Into<String>>(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = S>,
    ) -> &mut Table {
        self.push(
            name,
            Values::Text(values.into_iter().map(Into::into).collect()),
        )
    }

    /// Adds a column of yes/no values, written `true`/`false`, missing where None.
    pub fn flags(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = Option<bool>>,
    ) -> &mut Table {
        self.text(
            name,
            values
                .into_iter()
                .map(|b| b.map_or(String::new(), |b| b.to_string())),
        )
    }
}

impl Values {
    /// The number of values.
    pub fn len(&self) -> usize {
        match self {
            Values::Numbers(v) => v.len(),
            Values::Counts(v) => v.len(),
            Values::Text(v) => v.len(),
        }
    }

    /// True when there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Roller (or other) indices as one text cell, separated by spaces.
pub fn index_list(indices: impl IntoIterator<Item = usize>) -> String {
    indices
        .into_iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_values_are_not_finite_numbers_and_empty_text() {
        let mut t = Table::new("t");
        t.counts("n", [1, 2])
            .optional("x", [Some(0.5), None])
            .flags("stable", [Some(true), None]);
        assert_eq!(t.rows(), 2);
        assert_eq!(t.cell(0, 0), Cell::Number(1.0));
        assert_eq!(
            t.column("n").map(|c| &c.values),
            Some(&Values::Counts(vec![1, 2]))
        );
        assert_eq!(t.cell(1, 1), Cell::Missing);
        assert_eq!(t.cell(0, 2), Cell::Text("true"));
        assert_eq!(t.cell(1, 2), Cell::Missing);
        assert_eq!(t.column("x").map(|c| c.values.len()), Some(2));
    }
}
