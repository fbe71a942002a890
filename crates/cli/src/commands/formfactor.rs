//! `irradia formfactor CASE --PARAM value ...`: the lecture's closed-form form factors
//! ("Form Factor Examples 1-3").

use crate::error::CliError;
use clap::Args;
use irradia_radiosity::formfactor::analytic::{lookup, CASES};

#[derive(Args, Debug)]
#[command(
    after_long_help = cases_help(),
    allow_hyphen_values = true,
    disable_help_flag = false,
)]
pub struct FormFactorArgs {
    /// The case (see the list below), or `list`.
    #[arg(value_name = "CASE")]
    pub case: String,
    /// The case's parameters as `--name value` pairs (lengths in any one unit, angles in
    /// radians).
    #[arg(value_name = "--PARAM VALUE", trailing_var_arg = true, allow_hyphen_values = true, num_args = 0..)]
    pub params: Vec<String>,
}

fn cases_help() -> String {
    let mut s = String::from("Cases (lecture, \"Form Factor Examples 1-3\"):\n");
    for c in CASES {
        let ps: Vec<String> = c.params.iter().map(|(p, _)| format!("--{p} X")).collect();
        s.push_str(&format!(
            "  {} {}\n      {}\n",
            c.name,
            ps.join(" "),
            c.geometry
        ));
        for (p, what) in c.params {
            s.push_str(&format!("        --{p}: {what}\n"));
        }
    }
    s.push_str("\nExamples:\n  irradia formfactor element-coaxial-disk --h 1 --r 1      # 0.5\n  irradia formfactor perpendicular-rectangles --h 1 --l 1 --w 1   # 0.2000438\n  irradia formfactor list\nExit codes: 0 done, 2 bad input.");
    s
}

pub fn run(a: FormFactorArgs) -> Result<(), CliError> {
    if a.case == "list" {
        for c in CASES {
            let ps: Vec<String> = c.params.iter().map(|(p, _)| format!("--{p}")).collect();
            println!("{:<34} {}", c.name, ps.join(" "));
        }
        return Ok(());
    }
    let case = lookup(&a.case).map_err(CliError::Input)?;
    let mut given = Vec::new();
    let mut it = a.params.iter();
    while let Some(k) = it.next() {
        let Some(name) = k.strip_prefix("--") else {
            return Err(CliError::Input(format!(
                "expected --PARAM VALUE pairs, found '{k}'"
            )));
        };
        let (name, value) = match name.split_once('=') {
            Some((n, v)) => (n.to_string(), v.to_string()),
            None => {
                let v = it
                    .next()
                    .ok_or_else(|| CliError::Input(format!("--{name} needs a value")))?;
                (name.to_string(), v.clone())
            }
        };
        let v: f64 = value
            .parse()
            .map_err(|_| CliError::Input(format!("--{name} {value}: not a number")))?;
        given.push((name, v));
    }
    let f = case.eval_named(&given).map_err(CliError::Input)?;
    println!("{f:.10}");
    Ok(())
}
