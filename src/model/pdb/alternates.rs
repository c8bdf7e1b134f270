//! Alternate locations: one atom per site.
//!
//! `pdbtbx` copies the atoms without an alt-loc into every alternate
//! conformer of their residue (dividing their occupancy). The copies are
//! recognised (same serial, name and position) and kept once; per atom name
//! the alternate with the highest occupancy wins, ties going to the one that
//! appears first in the file, which also resolves microheterogeneity
//! (alternates with different residue names). Afterwards the atoms are put
//! back in serial order when their serials are distinct.

use std::collections::{HashMap, HashSet};

use pdbtbx::Atom;

/// One atom with the hierarchy it came from.
pub(super) struct Site<'a> {
    pub(super) atom: &'a Atom,
    pub(super) chain: &'a str,
    pub(super) residue: &'a str,
    pub(super) seq: isize,
    pub(super) insertion: &'a str,
}

/// Keeps one atom per site among `sites[first..]` (one residue's conformers):
/// copies of shared atoms are dropped, then per atom name the highest
/// occupancy wins, ties to the earliest.
pub(super) fn resolve_alternates(sites: &mut Vec<Site<'_>>, first: usize) {
    let tail: Vec<Site<'_>> = sites.drain(first..).collect();
    let mut seen: HashSet<(usize, &str, [u64; 3])> = HashSet::new();
    let mut best: Vec<Site<'_>> = Vec::new();
    let mut slot: HashMap<&str, usize> = HashMap::new();
    for site in tail {
        let a = site.atom;
        let (x, y, z) = a.pos();
        if !seen.insert((
            a.serial_number(),
            a.name(),
            [x.to_bits(), y.to_bits(), z.to_bits()],
        )) {
            continue;
        }
        match slot.get(a.name()) {
            Some(&i) => {
                if a.occupancy() > best[i].atom.occupancy() {
                    best[i] = site;
                }
            }
            None => {
                slot.insert(a.name(), best.len());
                best.push(site);
            }
        }
    }
    sites.extend(best);
}

/// Sorts by serial number when the serials are all distinct (file order in an
/// ordinary file); otherwise leaves `pdbtbx`'s chain-grouped order.
pub(super) fn order_by_serial(sites: &mut [Site<'_>]) {
    if sites
        .windows(2)
        .all(|w| w[0].atom.serial_number() < w[1].atom.serial_number())
    {
        return;
    }
    let mut serials: Vec<usize> = sites.iter().map(|s| s.atom.serial_number()).collect();
    serials.sort_unstable();
    if serials.windows(2).all(|w| w[0] != w[1]) {
        sites.sort_by_key(|s| s.atom.serial_number());
    }
}
