#![allow(clippy::unwrap_used)]

//! MOL2 text made from SDF text, so tests compare the two readers on the
//! same molecules without keeping converted files.

/// The first record of a V2000 SDF rewritten as MOL2: the same atoms in
/// the same order (SYBYL type = the element), the same bonds (type 4 as
/// `ar`), formal charges as `UNITY_ATOM_ATTR` attributes.
pub fn from_sdf(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let counts = lines[3];
    let n: usize = counts[0..3].trim().parse().unwrap();
    let nb: usize = counts[3..6].trim().parse().unwrap();
    let mut atoms = String::new();
    let mut attrs = String::new();
    for (i, l) in lines[4..4 + n].iter().enumerate() {
        let f: Vec<&str> = l.split_whitespace().collect();
        let (x, y, z, e) = (f[0], f[1], f[2], f[3]);
        atoms += &format!("{:>7} {e}{} {x} {y} {z} {e} 1 LIG 0.0\n", i + 1, i + 1);
        let charge = match l.get(36..39).map(str::trim) {
            Some("1") => 3,
            Some("2") => 2,
            Some("3") => 1,
            Some("5") => -1,
            Some("6") => -2,
            Some("7") => -3,
            _ => 0,
        };
        if charge != 0 {
            attrs += &format!("{} 1\ncharge {charge}\n", i + 1);
        }
    }
    for l in &lines[4 + n..] {
        if let Some(rest) = l.strip_prefix("M  CHG") {
            let v: Vec<i64> = rest
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            for p in v[1..].chunks(2) {
                attrs += &format!("{} 1\ncharge {}\n", p[0], p[1]);
            }
        }
    }
    let mut bonds = String::new();
    for (k, l) in lines[4 + n..4 + n + nb].iter().enumerate() {
        let a: usize = l[0..3].trim().parse().unwrap();
        let b: usize = l[3..6].trim().parse().unwrap();
        let kind = match l[6..9].trim() {
            "4" => "ar".to_string(),
            o => o.to_string(),
        };
        bonds += &format!("{} {a} {b} {kind}\n", k + 1);
    }
    format!(
        "@<TRIPOS>MOLECULE\nLIG\n {n} {nb} 1 0 0\nSMALL\nNO_CHARGES\n\n\
         @<TRIPOS>ATOM\n{atoms}@<TRIPOS>UNITY_ATOM_ATTR\n{attrs}@<TRIPOS>BOND\n{bonds}"
    )
}
