//! Pearson's chi-square test for the sampling tests (the p-value through the
//! regularised incomplete gamma function of the statrs crate).
#![allow(dead_code)]

/// The p-value of `observed` counts against `expected` ones (same total), after pooling
/// bins that expect fewer than 5 samples into one (Mitsuba's and pbrt's practice).
pub fn pearson(observed: &[f64], expected: &[f64]) -> f64 {
    let (mut chi2, mut dof) = (0.0, 0usize);
    let (mut pooled_o, mut pooled_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pooled_o += o;
            pooled_e += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pooled_e >= 5.0 {
        chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
        dof += 1;
    } else if pooled_o > 5.0 + 10.0 * pooled_e {
        // Samples where the density says there are almost none.
        return 0.0;
    }
    gamma_q(0.5 * (dof.max(2) - 1) as f64, 0.5 * chi2)
}

/// The regularised upper incomplete gamma function Q(a, x) (statrs), the chi-square
/// p-value of the statistic 2x with 2a degrees of freedom; 1 at x = 0.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        1.0
    } else {
        statrs::function::gamma::gamma_ur(a, x)
    }
}
