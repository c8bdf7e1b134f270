//! Two ways of asking a collider for the atoms in a ball, so a caller that
//! asks many times can be compiled once for each.

use glam::{Vec3, Vec4};

use super::Collider;
use crate::collide::padded_rows::PaddedRows;

/// A way to ask a collider for the atoms in a ball: [`Collider::near`],
/// split by whether the padded rows are there, so a caller that asks many
/// times (a move-to-touch query) can be compiled once for each and carry
/// only one of the two searches inlined where it asks, not both.
pub(crate) trait Search {
    /// As [`Collider::near`].
    fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F);
}

/// The plain index: brute force, a grid before its rows are built.
pub(crate) struct PlainSearch<'a>(pub &'a Collider);

impl Search for PlainSearch<'_> {
    #[inline(always)]
    fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F) {
        self.0.near_plain(p, radius, f);
    }
}

/// A grid with its padded rows: balls up to their margin from the rows,
/// larger ones from the plain grid.
pub(crate) struct RowSearch<'a> {
    /// The collider.
    pub collider: &'a Collider,
    /// Its rows.
    pub rows: &'a PaddedRows,
}

impl Search for RowSearch<'_> {
    #[inline(always)]
    fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F) {
        let c = self.collider;
        if radius <= self.rows.margin() {
            self.rows.near(p, radius, f);
        } else {
            c.near_plain(p, radius, f);
        }
    }
}
