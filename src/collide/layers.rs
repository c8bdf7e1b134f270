//! The optional layers that make the queries fast, each of which can be
//! turned off for measurement: answers are the same with or without any of
//! them (the tests check it), only their cost differs. The benchmark
//! report's section "Optimisation layers" times every query kind with all
//! layers on against each one off, alternately in one run.
//!
//! - [`Layers::clearance_map`]: the grids' [`super::clearance::Clearance`]
//!   map, which proves drug atoms (and groups of them) far from every
//!   receptor atom without a grid search.
//! - [`Layers::padded_rows`]: the grids' atoms again in
//!   [`super::padded_rows::PaddedRows`], so a drug atom's search scans one
//!   run of atoms instead of one per row of cells.
//! - [`Layers::compact_groups`]: the drug's atoms taken four at a time in
//!   groups of atoms close together ([`super::grouping`]) rather than in
//!   file order, so the groups' bounding balls are small.
//! - [`Layers::group_balls`]: each group's bounding ball tested first
//!   (against the receptor's box and the clearance map), four groups at
//!   once, so a group far from the receptor costs one test, not four.

/// Which optional layers a collider and a drug use (all by default).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layers {
    /// The grids build a clearance map.
    pub clearance_map: bool,
    /// The grids build padded rows.
    pub padded_rows: bool,
    /// The drug's groups of four are spatially compact.
    pub compact_groups: bool,
    /// The groups' bounding balls are tested before their atoms.
    pub group_balls: bool,
}

impl Default for Layers {
    fn default() -> Self {
        Self::ALL
    }
}

impl Layers {
    /// Every layer on: what the program uses.
    pub const ALL: Self = Self {
        clearance_map: true,
        padded_rows: true,
        compact_groups: true,
        group_balls: true,
    };

    /// The layers' names, in the order of the fields.
    pub const NAMES: [&'static str; 4] = [
        "clearance map",
        "padded rows",
        "compact groups",
        "group balls",
    ];

    /// Every layer on but the one named `name` (one of [`Layers::NAMES`]);
    /// `None` for another name.
    pub fn without(name: &str) -> Option<Self> {
        let mut l = Self::ALL;
        let flag = match name {
            "clearance map" => &mut l.clearance_map,
            "padded rows" => &mut l.padded_rows,
            "compact groups" => &mut l.compact_groups,
            "group balls" => &mut l.group_balls,
            _ => return None,
        };
        *flag = false;
        Some(l)
    }
}

#[cfg(test)]
mod tests {
    use super::Layers;

    #[test]
    fn each_name_turns_off_its_own_layer() {
        let mut seen = Vec::new();
        for name in Layers::NAMES {
            let l = Layers::without(name).expect("a layer");
            let flags = [
                l.clearance_map,
                l.padded_rows,
                l.compact_groups,
                l.group_balls,
            ];
            assert_eq!(flags.iter().filter(|f| !**f).count(), 1, "{name}");
            assert!(!seen.contains(&l), "{name}");
            seen.push(l);
        }
        assert!(Layers::without("turbo").is_none());
        assert_eq!(Layers::default(), Layers::ALL);
    }
}
