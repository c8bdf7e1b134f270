//! The state machine over a CIF file's lines: text fields, items and
//! loops of the first data block, the kept categories' rows gathered into
//! [`Row`]s and handed to the `_atom_site` and `_struct_conn` readers, and
//! the checks on a loop's or an item group's shape (rows cut short, values
//! missing) that name the line and column.

use super::atom_site::{AtomColumns, AtomSite};
use super::row::{Cell, Row, RowView};
use super::struct_conn::{ConnColumns, StructConn};
use super::tokens::{Kind, Token, tokenize};
use super::{MAX_BOND_WARNINGS, MAX_TEXT_FIELD};
use crate::model::LoadError;
use crate::model::pdb::Raw;
use crate::text::excerpt;

/// The categories kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Category {
    AtomSite,
    StructConn,
}

impl Category {
    /// The category of tag `_category.item`, when it is one kept, with the
    /// item.
    pub(super) fn of_tag(tag: &str) -> Option<(Self, &str)> {
        let (category, item) = tag.get(1..)?.split_once('.')?;
        if category.eq_ignore_ascii_case("atom_site") {
            Some((Category::AtomSite, item))
        } else if category.eq_ignore_ascii_case("struct_conn") {
            Some((Category::StructConn, item))
        } else {
            None
        }
    }

    pub(super) fn name(self) -> &'static str {
        match self {
            Category::AtomSite => "_atom_site",
            Category::StructConn => "_struct_conn",
        }
    }
}

/// Where the reader is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Mode {
    /// Between items and loops.
    Top,
    /// After a tag outside a loop: its value comes next (kept when the tag
    /// is one of a kept category's, at that column).
    Value(Option<usize>),
    /// After `loop_`: reading its tags.
    Header,
    /// Reading a loop's values.
    Body,
}

/// The state of a CIF read.
pub(super) struct CifReader<'a> {
    pub(super) label: &'a str,
    pub(super) mode: Mode,
    /// A `data_` line was seen.
    pub(super) in_block: bool,
    /// The text field being read: its first line, its text (up to
    /// [`MAX_TEXT_FIELD`]) and whether it was cut.
    pub(super) text_field: Option<(usize, String, bool)>,
    /// The current loop's or item group's category, when kept.
    pub(super) category: Option<Category>,
    /// The current loop's item names (kept categories only).
    pub(super) columns: Vec<String>,
    /// The current loop's column count.
    pub(super) width: usize,
    /// Values of the current loop read so far (for skipped loops, to know
    /// where rows end: not needed, but counted for the loop's own check).
    pub(super) values: usize,
    /// Line of the current `loop_`.
    pub(super) loop_line: usize,
    /// The row being read.
    pub(super) row: Row,
    /// Rows of this loop come one per line (its first row did).
    pub(super) one_per_line: Option<bool>,
    pub(super) atoms: AtomSite,
    pub(super) bonds: StructConn,
    pub(super) raw: Raw,
}

impl<'a> CifReader<'a> {
    pub(super) fn new(label: &'a str) -> Self {
        Self {
            label,
            mode: Mode::Top,
            in_block: false,
            text_field: None,
            category: None,
            columns: Vec::new(),
            width: 0,
            values: 0,
            loop_line: 0,
            row: Row::default(),
            one_per_line: None,
            atoms: AtomSite::default(),
            bonds: StructConn::default(),
            raw: Raw::default(),
        }
    }

    pub(super) fn error(
        &self,
        line: usize,
        column: Option<usize>,
        reason: impl Into<String>,
    ) -> LoadError {
        LoadError::parse_at(self.label, Some(line), column, reason)
    }

    /// Reads line `number`; true when the first data block has ended.
    pub(super) fn line(
        &mut self,
        number: usize,
        line: &str,
        tokens: &mut Vec<Token>,
    ) -> Result<bool, LoadError> {
        if let Some((_, text, cut)) = &mut self.text_field {
            if let Some(rest) = line.strip_prefix(';') {
                let Some((first, text, cut)) = self.text_field.take() else {
                    return Ok(false);
                };
                self.value(&text, true, first, 1, cut)?;
                return self.tokens(number, rest, 1, tokens);
            }
            if !*cut {
                if text.len() + line.len() < MAX_TEXT_FIELD {
                    text.push('\n');
                    text.push_str(line);
                } else {
                    *cut = true;
                }
            }
            return Ok(false);
        }
        if let Some(rest) = line.strip_prefix(';') {
            let cut = rest.len() > MAX_TEXT_FIELD;
            let text = if cut { String::new() } else { rest.to_string() };
            self.text_field = Some((number, text, cut));
            return Ok(false);
        }
        self.tokens(number, line, 0, tokens)
    }

    /// Handles the tokens of `line` (which starts at byte `offset` of the
    /// file's line `number`); true when the first data block has ended.
    pub(super) fn tokens(
        &mut self,
        number: usize,
        line: &str,
        offset: usize,
        tokens: &mut Vec<Token>,
    ) -> Result<bool, LoadError> {
        tokenize(line, tokens);
        if tokens.is_empty() {
            return Ok(false);
        }
        // Lines are ASCII here (`ascii_line`): a byte is a column.
        let column =
            |t: &Token| offset + 1 + t.start.saturating_sub(usize::from(t.kind == Kind::Quoted));
        // Rows one per line: a line of values only, at a row's start, is
        // one row, and its values must fill it.
        if self.mode == Mode::Body
            && self.category.is_some()
            && self.row.cells.is_empty()
            && self.one_per_line == Some(true)
            && tokens
                .iter()
                .all(|t| matches!(t.kind, Kind::Bare | Kind::Quoted))
            && tokens.len() != self.width
        {
            let (category, n) = (self.category_name(), self.width);
            return Err(self.error(
                number,
                Some(column(&tokens[0])),
                format!(
                    "this {category} row has {} values; the loop has {n} columns",
                    tokens.len()
                ),
            ));
        }
        // The common case, a whole row on its line (its values were
        // counted above): read in place.
        if self.mode == Mode::Body
            && self.category.is_some()
            && self.row.cells.is_empty()
            && self.one_per_line == Some(true)
            && tokens
                .iter()
                .all(|t| matches!(t.kind, Kind::Bare | Kind::Quoted))
        {
            self.row.cells.clear();
            self.row.cells.extend(tokens.iter().map(|t| Cell {
                start: t.start,
                end: t.end,
                quoted: t.kind == Kind::Quoted,
                line: number,
                column: column(t),
            }));
            self.values += tokens.len();
            let result = self.emit(line);
            self.row.cells.clear();
            return result.map(|()| false);
        }
        let first_row = matches!(self.mode, Mode::Header | Mode::Body)
            && self.one_per_line.is_none()
            && self.row.cells.is_empty()
            && matches!(tokens[0].kind, Kind::Bare | Kind::Quoted);
        for (k, t) in tokens.iter().enumerate() {
            let text = &line[t.start..t.end];
            let col = column(t);
            match t.kind {
                Kind::Bare | Kind::Quoted => {
                    self.value(text, t.kind == Kind::Quoted, number, col, false)?;
                    if first_row
                        && self.one_per_line.is_none()
                        && self.row.cells.is_empty()
                        && self.values > 0
                    {
                        // The loop's first row ended on this token.
                        self.one_per_line = Some(k + 1 == tokens.len());
                    }
                }
                Kind::Tag => {
                    self.missing_value(number, col)?;
                    if self.mode == Mode::Body {
                        self.end_of_loop()?;
                    }
                    self.tag(text, number)?;
                }
                Kind::Loop => {
                    self.missing_value(number, col)?;
                    self.end_of_loop()?;
                    self.end_of_items()?;
                    self.mode = Mode::Header;
                    self.category = None;
                    self.columns.clear();
                    self.width = 0;
                    self.values = 0;
                    self.loop_line = number;
                    self.one_per_line = None;
                }
                Kind::Data => {
                    self.missing_value(number, col)?;
                    self.end_of_loop()?;
                    self.end_of_items()?;
                    if self.in_block {
                        return Ok(true);
                    }
                    self.in_block = true;
                    self.mode = Mode::Top;
                }
                Kind::Reserved => {
                    self.missing_value(number, col)?;
                    self.end_of_loop()?;
                    self.end_of_items()?;
                }
            }
        }
        if first_row && self.one_per_line.is_none() && !self.row.cells.is_empty() {
            self.one_per_line = Some(false);
        }
        Ok(false)
    }

    pub(super) fn category_name(&self) -> &'static str {
        self.category.map_or("", Category::name)
    }

    /// A tag outside a loop's body.
    pub(super) fn tag(&mut self, tag: &str, line: usize) -> Result<(), LoadError> {
        let kept = Category::of_tag(tag);
        if self.mode == Mode::Header {
            if self.width == 0 {
                self.category = kept.map(|(c, _)| c);
            }
            self.width += 1;
            if self.category.is_some() {
                let item = match kept {
                    Some((c, item)) if Some(c) == self.category => item,
                    _ => "",
                };
                self.columns.push(item.to_ascii_lowercase());
            }
            return Ok(());
        }
        // An item outside a loop: a kept category's items make one row.
        match kept {
            Some((c, item)) => {
                if self.category != Some(c) {
                    self.end_of_items()?;
                    self.category = Some(c);
                    self.loop_line = line;
                }
                self.columns.push(item.to_ascii_lowercase());
                self.mode = Mode::Value(Some(self.columns.len() - 1));
            }
            None => {
                self.end_of_items()?;
                self.mode = Mode::Value(None);
            }
        }
        Ok(())
    }

    /// A value (of a loop or an item), at `line` and `column`; `cut` when
    /// it is a text field too long to keep.
    pub(super) fn value(
        &mut self,
        text: &str,
        quoted: bool,
        line: usize,
        column: usize,
        cut: bool,
    ) -> Result<(), LoadError> {
        match self.mode {
            Mode::Top => Ok(()),
            Mode::Value(None) => {
                self.mode = Mode::Top;
                Ok(())
            }
            Mode::Value(Some(_)) => {
                if cut {
                    return Err(self.error(
                        line,
                        Some(column),
                        "a text field too long for an atom or bond value",
                    ));
                }
                self.row.push(text, quoted, line, column);
                self.mode = Mode::Top;
                Ok(())
            }
            Mode::Header => {
                self.mode = Mode::Body;
                if self.category.is_some() {
                    self.begin_table()?;
                }
                self.value(text, quoted, line, column, cut)
            }
            Mode::Body => {
                self.values += 1;
                if self.category.is_none() {
                    return Ok(());
                }
                if cut {
                    return Err(self.error(
                        line,
                        Some(column),
                        "a text field too long for an atom or bond value",
                    ));
                }
                self.row.push(text, quoted, line, column);
                if self.row.cells.len() == self.width {
                    self.emit_row()?;
                    self.row.clear();
                }
                Ok(())
            }
        }
    }

    /// The column layout of a kept loop (or item group), before its rows.
    pub(super) fn begin_table(&mut self) -> Result<(), LoadError> {
        let line = self.loop_line;
        match self.category {
            Some(Category::AtomSite) => {
                self.atoms.columns =
                    AtomColumns::find(&self.columns).map_err(|r| self.error(line, None, r))?;
            }
            Some(Category::StructConn) => self.bonds.columns = ConnColumns::find(&self.columns),
            None => {}
        }
        Ok(())
    }

    /// Hands a full row to its category.
    pub(super) fn emit_row(&mut self) -> Result<(), LoadError> {
        let text = std::mem::take(&mut self.row.text);
        let result = self.emit(&text);
        self.row.text = text;
        result
    }

    /// Hands the row whose cells are `self.row.cells`, spans of `text`, to
    /// its category.
    pub(super) fn emit(&mut self, text: &str) -> Result<(), LoadError> {
        let row = RowView {
            text,
            cells: &self.row.cells,
        };
        match self.category {
            Some(Category::AtomSite) => {
                self.atoms
                    .row(&row, &mut self.raw)
                    .map_err(|(cell, reason)| {
                        let c = row.cells.get(cell).copied();
                        LoadError::parse_at(
                            self.label,
                            c.map(|c| c.line),
                            c.map(|c| c.column),
                            reason,
                        )
                    })
            }
            Some(Category::StructConn) => {
                if let Err((cell, reason)) = self.bonds.row(&row, &mut self.raw) {
                    self.bonds.warnings += 1;
                    if self.bonds.warnings <= MAX_BOND_WARNINGS {
                        let c = row.cells.get(cell).copied();
                        self.raw.warnings.push(format!(
                            "{}:{}:{}: {reason}; the bond is skipped",
                            self.label,
                            c.map_or(0, |c| c.line),
                            c.map_or(0, |c| c.column)
                        ));
                    }
                }
                Ok(())
            }
            None => Ok(()),
        }
    }

    /// Ends a loop (a row left unfilled in a kept one is an error), or a
    /// loop of tags without values.
    pub(super) fn end_of_loop(&mut self) -> Result<(), LoadError> {
        match self.mode {
            Mode::Header => {}
            Mode::Body => {
                if let (Some(c), Some(first)) = (self.category, self.row.cells.first().copied()) {
                    return Err(self.error(
                        first.line,
                        Some(first.column),
                        format!(
                            "the {} loop ends inside a row: {} of its {} values are there",
                            c.name(),
                            self.row.cells.len(),
                            self.width
                        ),
                    ));
                }
            }
            Mode::Top | Mode::Value(_) => return Ok(()),
        }
        self.mode = Mode::Top;
        self.category = None;
        self.columns.clear();
        self.row.clear();
        Ok(())
    }

    /// A reserved word or tag where an item's value should be.
    pub(super) fn missing_value(&mut self, line: usize, column: usize) -> Result<(), LoadError> {
        match self.mode {
            Mode::Value(Some(k)) => {
                let item = self.columns.get(k).cloned().unwrap_or_default();
                Err(self.error(
                    line,
                    Some(column),
                    format!(
                        "the item {} has no value before this",
                        excerpt(&format!("{}.{item}", self.category_name()))
                    ),
                ))
            }
            Mode::Value(None) => {
                self.mode = Mode::Top;
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// Ends a group of items outside a loop: a kept category's make a row.
    pub(super) fn end_of_items(&mut self) -> Result<(), LoadError> {
        if matches!(self.mode, Mode::Header | Mode::Body) || self.category.is_none() {
            return Ok(());
        }
        if self.row.cells.len() == self.columns.len() && !self.columns.is_empty() {
            self.width = self.columns.len();
            self.begin_table()?;
            self.emit_row()?;
        }
        self.row.clear();
        self.columns.clear();
        self.category = None;
        Ok(())
    }

    /// The end of the text: what is left open is closed or refused.
    pub(super) fn finish(mut self, last_line: usize) -> Result<Raw, LoadError> {
        if let Some((first, _, _)) = &self.text_field {
            return Err(self.error(
                *first,
                Some(1),
                "a text field opened here (a line starting with ;) is never closed",
            ));
        }
        if let Mode::Value(Some(_)) = self.mode {
            return Err(self.error(
                last_line,
                None,
                "the file ends before the value of its last item",
            ));
        }
        self.end_of_loop()?;
        self.end_of_items()?;
        if self.bonds.warnings > MAX_BOND_WARNINGS {
            self.raw.warnings.push(format!(
                "{}: ... and {} more struct_conn bonds skipped",
                self.label,
                self.bonds.warnings - MAX_BOND_WARNINGS
            ));
        }
        Ok(self.raw)
    }
}
