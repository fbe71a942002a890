//! The named indices of refraction against pip Mitsuba 3.9.1 (scalar_rgb):
//! tests/data/mitsuba_ior.csv, written by tests/data/mitsuba_ior.py, holds the RGB
//! `(eta, k)` Mitsuba's `conductor` plugin gives every named material and the index of
//! every named dielectric.

use irradia_scatter::ior::*;

fn reference() -> Vec<Vec<String>> {
    include_str!("data/mitsuba_ior.csv")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 2e-4 * b.abs() + 2e-6
}

#[test]
fn conductors_reduce_to_mitsubas_rgb() {
    let rows: Vec<_> = reference()
        .into_iter()
        .filter(|r| r[0] == "conductor")
        .collect();
    assert_eq!(
        rows.len(),
        conductor_names().len(),
        "every name has a reference"
    );
    for r in rows {
        let v: Vec<f32> = r[2..8].iter().map(|s| s.parse().unwrap()).collect();
        let (eta, k) = conductor_ior(&r[1]).unwrap_or_else(|| panic!("{} unknown", r[1]));
        let got = [eta.r, eta.g, eta.b, k.r, k.g, k.b];
        for c in 0..6 {
            assert!(
                close(got[c], v[c]),
                "{} channel {c}: {} vs Mitsuba {}",
                r[1],
                got[c],
                v[c]
            );
        }
    }
    // Gold, spelled out: eta (0.143, 0.375, 1.442), k (3.983, 2.386, 1.603).
    let (eta, k) = conductor_ior("Au").unwrap();
    assert!((eta.r - 0.143036).abs() < 1e-5 && (k.b - 1.60336).abs() < 1e-4);
    assert_eq!(
        conductor_ior("none"),
        Some((irradia_core::Rgb::BLACK, irradia_core::Rgb::WHITE))
    );
    assert_eq!(conductor_ior("gold"), None);
    assert_eq!(
        conductor_ior("au"),
        None,
        "conductor names are case-sensitive, as Mitsuba's files"
    );
    assert!(conductor_names().contains(&"Cu") && conductor_names().contains(&"none"));
}

#[test]
fn dielectrics_are_mitsubas_table() {
    let rows: Vec<_> = reference()
        .into_iter()
        .filter(|r| r[0] == "dielectric")
        .collect();
    assert_eq!(rows.len(), dielectric_names().len());
    for r in rows {
        let want: f32 = r[2].parse().unwrap();
        assert_eq!(dielectric_ior(&r[1]), Some(want), "{}", r[1]);
    }
    assert_eq!(
        dielectric_ior("BK7"),
        Some(1.5046),
        "case-insensitive, as Mitsuba"
    );
    assert_eq!(dielectric_ior("glass"), None);
}

#[test]
fn every_embedded_table_parses_and_the_cie_table_is_complete() {
    for n in CONDUCTORS {
        let (eta, k) = conductor_ior(n).unwrap();
        assert!(eta.is_finite() && k.is_finite(), "{n}");
    }
    // ȳ peaks at 555 nm with 1; interpolation halfway between nodes.
    assert!((cie1931_xyz(555.0)[1] - 1.0).abs() < 1e-9);
    let mid = cie1931_xyz(552.5);
    assert!((mid[0] - 0.5 * (cie1931_xyz(550.0)[0] + cie1931_xyz(555.0)[0])).abs() < 1e-12);
    assert_eq!(cie1931_xyz(830.0)[1], 0.00000045181);
    assert_eq!(cie1931_xyz(900.0), [0.0; 3]);
    assert!(parse_spd("# c\n400 1\n500 x\n").is_err());
}
