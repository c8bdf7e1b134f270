//! A row of a kept category: the values' text in one buffer with where
//! each value was (line, column, quoted or not) while it is read, and the
//! view of a full row that the `_atom_site` and `_struct_conn` readers take
//! values from (`?` and `.` unquoted read as absent).

/// One value of a row: its text (in the row's buffer), whether it was
/// quoted, and where it was.
#[derive(Debug, Clone, Copy)]
pub(super) struct Cell {
    pub(super) start: usize,
    pub(super) end: usize,
    pub(super) quoted: bool,
    pub(super) line: usize,
    pub(super) column: usize,
}

/// A row being read: the values' text and their cells.
#[derive(Debug, Default)]
pub(super) struct Row {
    pub(super) text: String,
    pub(super) cells: Vec<Cell>,
}

impl Row {
    pub(super) fn clear(&mut self) {
        self.text.clear();
        self.cells.clear();
    }

    pub(super) fn push(&mut self, value: &str, quoted: bool, line: usize, column: usize) {
        let start = self.text.len();
        self.text.push_str(value);
        self.cells.push(Cell {
            start,
            end: self.text.len(),
            quoted,
            line,
            column,
        });
    }
}

/// A full row: its values' text and where each was.
pub(super) struct RowView<'r> {
    pub(super) text: &'r str,
    pub(super) cells: &'r [Cell],
}

impl<'r> RowView<'r> {
    /// The value at `column` as written (empty when there is none).
    pub(super) fn raw(&self, column: usize) -> &'r str {
        self.cells
            .get(column)
            .and_then(|c| self.text.get(c.start..c.end))
            .unwrap_or("")
    }

    /// The value at `column`, unless it is absent, `?` or `.` unquoted.
    pub(super) fn get(&self, column: Option<usize>) -> Option<&'r str> {
        let c = column?;
        let cell = self.cells.get(c)?;
        let v = self.text.get(cell.start..cell.end)?;
        (cell.quoted || (v != "?" && v != ".")).then_some(v)
    }
}

/// A problem with a row: the index of the value it is about and the message.
pub(super) type RowError = (usize, String);
