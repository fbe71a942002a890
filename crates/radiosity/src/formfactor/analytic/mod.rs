//! The lecture's closed-form catalogue ("Form Factor Examples 1-3", after Siegel and
//! Howell, "Thermal Radiation Heat Transfer", appendix of configuration factors), one
//! file per group of cases, and the analytic matrix method (`polygon`).
//!
//! Each case has a name (`irradia formfactor CASE`), the geometry in words, its
//! parameters, and a function of them. Every case is checked in
//! `tests/analytic_catalogue.rs` against an independent numerical integration of the
//! form-factor integral over the same geometry.

pub mod cylinders;
pub mod disks;
pub mod enclosure;
pub mod polygon;
pub mod rectangles;
pub mod strips;

/// One closed-form case of the catalogue.
pub struct Case {
    pub name: &'static str,
    /// The lecture's description and the coordinates used by the numerical check.
    pub geometry: &'static str,
    /// Parameter names (as `--name value`) and what they mean.
    pub params: &'static [(&'static str, &'static str)],
    /// The form factor from the parameters, in the order of `params`.
    pub eval: fn(&[f64]) -> Result<f64, String>,
}

/// The whole catalogue, in the lecture's order.
pub const CASES: &[Case] = &[
    strips::STRIP_TO_STRIP,
    rectangles::ELEMENT_PARALLEL_RECTANGLE,
    strips::STRIP_PARALLEL_RECTANGLE,
    rectangles::ELEMENT_PERPENDICULAR_RECTANGLE,
    rectangles::PERPENDICULAR_RECTANGLES,
    enclosure::THREE_PLANE_ENCLOSURE,
    disks::ELEMENT_COAXIAL_DISK,
    disks::ELEMENT_OFFSET_DISK,
    disks::ELEMENT_PERPENDICULAR_DISK,
    disks::ELEMENT_ELLIPTICAL_PLATE,
    cylinders::STRIP_CYLINDER,
    disks::COAXIAL_DISKS,
    cylinders::CYLINDER_ELEMENT_PLANE,
];

pub fn find(name: &str) -> Option<&'static Case> {
    CASES.iter().find(|c| c.name == name)
}

/// [`find`], with an unknown name an error that lists the cases (`irradia formfactor`
/// and the Python binding's `irradia.form_factor` say the same).
pub fn lookup(name: &str) -> Result<&'static Case, String> {
    find(name).ok_or_else(|| {
        let names: Vec<&str> = CASES.iter().map(|c| c.name).collect();
        format!(
            "unknown form-factor case '{name}'; the cases are: {}",
            names.join(", ")
        )
    })
}

impl Case {
    /// Evaluates with named parameters; errors name the missing or bad parameter.
    pub fn eval_named(&self, given: &[(String, f64)]) -> Result<f64, String> {
        let mut vals = Vec::with_capacity(self.params.len());
        for (p, what) in self.params {
            match given.iter().find(|(n, _)| n == p) {
                Some((_, v)) if v.is_finite() => vals.push(*v),
                Some((_, v)) => return Err(format!("--{p} {v} is not a finite number")),
                None => return Err(format!("case '{}' needs --{p} ({what})", self.name)),
            }
        }
        for (n, _) in given {
            if !self.params.iter().any(|(p, _)| p == n) {
                let names: Vec<String> =
                    self.params.iter().map(|(p, _)| format!("--{p}")).collect();
                return Err(format!(
                    "case '{}' has no parameter --{n}; it takes {}",
                    self.name,
                    names.join(" ")
                ));
            }
        }
        (self.eval)(&vals)
    }
}

pub(crate) fn positive(name: &str, v: f64) -> Result<f64, String> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(format!("--{name} must be a positive length (got {v})"))
    }
}
