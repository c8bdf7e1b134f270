//! Short text kept inline: the atom, residue, chain, insertion-code and
//! element labels of every atom ([`super::AtomInfo`]).
//!
//! A 272k-atom structure has 272k of each; as `String`s they would take 24
//! bytes each plus a heap block, more than everything else an atom holds. A
//! [`Label<N>`] is `N` bytes, in place, padded with NUL bytes, and reads as
//! a `&str` wherever one is wanted (it derefs to `str`, prints with
//! `Display`, compares with `str` and `String`, serialises as a string).
//!
//! The readers take a label with [`Label::new`], which refuses text longer
//! than `N` bytes (they say so, naming the line); [`From`] conversions, for
//! labels made in code, cut longer text at a character boundary and at a
//! NUL byte, which no label holds.

use std::borrow::Borrow;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::ops::Deref;

use serde::{Serialize, Serializer};

/// An atom name (`CA`, `O5'`; SDF: element and index, `Cl12`).
pub type AtomName = Label<8>;
/// A residue name (`ALA`, a 5-character CCD code; SDF: the title, cut).
pub type ResidueName = Label<8>;
/// A chain identifier (the PDB's are at most 4 characters).
pub type ChainId = Label<5>;
/// An insertion code (one character in every format).
pub type InsertionCode = Label<2>;
/// An element symbol, normalised (`C`, `Cl`), or an unknown one as written.
pub type ElementSymbol = Label<3>;

/// Text of at most `N` bytes of UTF-8 without NUL, stored inline.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Label<const N: usize>([u8; N]);

impl<const N: usize> Label<N> {
    /// Most bytes the label holds.
    pub const CAPACITY: usize = N;

    /// The empty label.
    pub const EMPTY: Self = Self([0; N]);

    /// `text` as a label, or `None` when it is longer than `N` bytes or
    /// holds a NUL byte.
    pub fn new(text: &str) -> Option<Self> {
        let bytes = text.as_bytes();
        if bytes.len() > N || bytes.contains(&0) {
            return None;
        }
        let mut out = [0; N];
        out[..bytes.len()].copy_from_slice(bytes);
        Some(Self(out))
    }

    /// `text` cut at its first NUL byte and then to at most `N` bytes at a
    /// character boundary.
    pub fn truncated(text: &str) -> Self {
        let text = text.split('\0').next().unwrap_or_default();
        let mut end = text.len().min(N);
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let mut out = [0; N];
        out[..end].copy_from_slice(&text.as_bytes()[..end]);
        Self(out)
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        let len = self.0.iter().position(|&b| b == 0).unwrap_or(N);
        // Built from a `&str` cut at a character boundary: always UTF-8.
        std::str::from_utf8(&self.0[..len]).unwrap_or_default()
    }
}

impl<const N: usize> Default for Label<N> {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl<const N: usize> Deref for Label<N> {
    type Target = str;

    fn deref(&self) -> &str {
        self.as_str()
    }
}

impl<const N: usize> AsRef<str> for Label<N> {
    fn as_ref(&self) -> &str {
        self.as_str()
    }
}

impl<const N: usize> Borrow<str> for Label<N> {
    fn borrow(&self) -> &str {
        self.as_str()
    }
}

impl<const N: usize> Hash for Label<N> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        // As `str` hashes, so that `Borrow<str>` lookups find it.
        self.as_str().hash(state);
    }
}

impl<const N: usize> fmt::Display for Label<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // `pad` keeps width and alignment (`{:<4}`).
        f.pad(self.as_str())
    }
}

impl<const N: usize> fmt::Debug for Label<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl<const N: usize> From<&str> for Label<N> {
    fn from(text: &str) -> Self {
        Self::truncated(text)
    }
}

impl<const N: usize> From<&String> for Label<N> {
    fn from(text: &String) -> Self {
        Self::truncated(text)
    }
}

impl<const N: usize> From<String> for Label<N> {
    fn from(text: String) -> Self {
        Self::truncated(&text)
    }
}

impl<const N: usize> From<Label<N>> for String {
    fn from(label: Label<N>) -> Self {
        label.as_str().to_string()
    }
}

impl<const N: usize> PartialEq<str> for Label<N> {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl<const N: usize> PartialEq<&str> for Label<N> {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl<const N: usize> PartialEq<String> for Label<N> {
    fn eq(&self, other: &String) -> bool {
        self.as_str() == other
    }
}

impl<const N: usize> PartialEq<Label<N>> for str {
    fn eq(&self, other: &Label<N>) -> bool {
        self == other.as_str()
    }
}

impl<const N: usize> PartialEq<Label<N>> for &str {
    fn eq(&self, other: &Label<N>) -> bool {
        *self == other.as_str()
    }
}

impl<const N: usize> PartialEq<Label<N>> for String {
    fn eq(&self, other: &Label<N>) -> bool {
        self == other.as_str()
    }
}

impl<const N: usize> Serialize for Label<N> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn labels_read_as_the_text_they_hold() {
        let l: Label<8> = "CA".into();
        assert_eq!(l, "CA");
        assert_eq!("CA", l);
        assert_eq!(l, String::from("CA"));
        assert_eq!(&*l, "CA");
        assert_eq!(l.len(), 2);
        assert_eq!(
            format!("[{l}] [{l:<4}] [{l:>4}] {l:?}"),
            "[CA] [CA  ] [  CA] \"CA\""
        );
        assert!(Label::<4>::default().is_empty());
        assert_eq!(serde_json::to_string(&l).unwrap(), "\"CA\"");
        let full = Label::<4>::new("ABCD").unwrap();
        assert_eq!(full.as_str(), "ABCD");
        assert!(Label::<4>::new("ABCDE").is_none());
        assert!(Label::<4>::new("A\0").is_none());
    }

    #[test]
    fn conversions_cut_at_a_character_boundary() {
        assert_eq!(Label::<4>::from("ABCDEF"), "ABCD");
        assert_eq!(Label::<4>::from("aéé"), "aé");
        assert_eq!(Label::<4>::from("ab\0cd"), "ab");
        assert_eq!(Label::<3>::from("€€"), "€");
    }

    #[test]
    fn labels_hash_and_order_as_text() {
        use std::collections::{BTreeSet, HashSet};
        let set: HashSet<Label<8>> = ["HOH", "ALA"].into_iter().map(Label::from).collect();
        assert!(set.contains("HOH"));
        let sorted: Vec<Label<8>> = ["B", "AB", "A", ""]
            .into_iter()
            .map(Label::from)
            .collect::<BTreeSet<_>>()
            .into_iter()
            .collect();
        assert_eq!(sorted, ["", "A", "AB", "B"]);
    }

    #[test]
    fn labels_are_small() {
        assert_eq!(std::mem::size_of::<Label<8>>(), 8);
        assert_eq!(std::mem::size_of::<Option<Label<4>>>(), 5);
        // An atom's identity and radius, as every structure keeps it.
        assert_eq!(std::mem::size_of::<crate::model::AtomInfo>(), 48);
    }
}
