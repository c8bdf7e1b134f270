//! Colour by contribution: which atoms take which colour of the diverging
//! scale ([`super::colors::contribution`]), and which of them changed.
//!
//! The drug's atoms and the receptor's atoms within 8 Å of it take the
//! colour of their Vina contribution ([`crate::session::LiveScore`]); all
//! others keep their element colour. Contributions are quantised to the
//! scale's steps, and [`ContributionColors::update`] returns only the atoms
//! whose step changed since the last update (or that enter or leave the
//! coloured set), so a frame uploads only those. Contact highlights are
//! drawn over these colours by the shader, as over element colours.

use std::collections::BTreeMap;

use super::colors::{contribution_level, level_color};
use crate::session::LiveScore;

/// An atom: (molecule, atom).
pub type AtomRef = (usize, usize);

/// The atoms coloured by contribution now, with their steps.
#[derive(Debug, Clone, Default)]
pub struct ContributionColors {
    levels: BTreeMap<AtomRef, i8>,
    /// The last update showed a score (else element colours).
    pub shown: bool,
}

impl ContributionColors {
    /// The steps `score` gives: the drug's scored atoms and the receptor's
    /// atoms within 8 Å.
    pub fn levels_of(score: &LiveScore) -> BTreeMap<AtomRef, i8> {
        let mut out = BTreeMap::new();
        for (a, e) in score.drug_atoms() {
            out.insert((score.drug, a as usize), contribution_level(e));
        }
        for &(a, e) in &score.receptor_atoms {
            out.insert((score.receptor, a as usize), contribution_level(e));
        }
        out
    }

    /// Moves to the colours of `score` (or to element colours everywhere
    /// with `None`): the atoms whose colour changes, with their new colour
    /// (`None`: back to the element's), in atom order.
    pub fn update(&mut self, score: Option<&LiveScore>) -> Vec<(usize, usize, Option<[f32; 3]>)> {
        self.shown = score.is_some();
        let new = score.map(Self::levels_of).unwrap_or_default();
        let mut changes = Vec::new();
        for (&(b, a), &l) in &new {
            if self.levels.get(&(b, a)) != Some(&l) {
                changes.push((b, a, Some(level_color(l))));
            }
        }
        for &(b, a) in self.levels.keys() {
            if !new.contains_key(&(b, a)) {
                changes.push((b, a, None));
            }
        }
        changes.sort_by_key(|c| (c.0, c.1));
        self.levels = new;
        changes
    }
}
