//! `irradia wall --config FILE [SCENE] -o DIR`: one rank per display renders its part of
//! the wall, blended and colour-corrected; writes `display-R-C.png` for each display,
//! `photo.png` (the simulated photograph) and `photo-uncorrected.png` (the same wall
//! driven naively, for comparison).

use crate::error::CliError;
use clap::Args;
use irradia_core::{Image, Rgb};
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::wall::{self, WallConfig, WallSource};
use irradia_parallel::workload::Workload;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct WallArgs {
    /// The wall file (TOML; see docs/parallel.md).
    #[arg(long)]
    pub config: PathBuf,
    /// What to show: teapot, random-triangles, marching-cubes, or grey (a uniform 50% grey calibration frame).
    #[arg(default_value = "teapot")]
    pub scene: String,
    /// Triangles for the workload.
    #[arg(long, default_value_t = 20_000)]
    pub triangles: usize,
    /// Output folder.
    #[arg(short, long)]
    pub output: PathBuf,
}

fn save(
    path: &std::path::Path,
    w: u32,
    h: u32,
    px: &[glam::Vec3],
    encoded: bool,
) -> Result<(), CliError> {
    // Drive values are already gamma-encoded for their projector: store them as they are.
    let pixels = px
        .iter()
        .map(|v| {
            let v = v.clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
            if encoded {
                let l = v.powf(2.2); // undo the sRGB-like encoding `save` applies
                Rgb::new(l.x, l.y, l.z)
            } else {
                Rgb::new(v.x, v.y, v.z)
            }
        })
        .collect();
    irradia_core::io::save(&Image::from_pixels(w, h, pixels), path)
        .map_err(|e| CliError::Failure(e.to_string()))
}

pub fn run(a: WallArgs) -> Result<(), CliError> {
    let c = WallConfig::load(&a.config).map_err(CliError::Input)?;
    let src = if a.scene == "grey" || a.scene == "gray" {
        WallSource::Uniform(glam::Vec3::splat(0.5))
    } else {
        WallSource::Workload(Workload::by_name(&a.scene, a.triangles).ok_or_else(|| {
            CliError::Input(format!(
                "scene {:?}: expected teapot, random-triangles, marching-cubes or grey",
                a.scene
            ))
        })?)
    };
    std::fs::create_dir_all(&a.output)
        .map_err(|e| CliError::Failure(format!("{}: {e}", a.output.display())))?;
    let (ww, wh) = c.wall_size();
    for corrected in [true, false] {
        let out = run_local(c.displays(), LocalOptions::default(), |comm| {
            wall::frame(comm, &c, &src, corrected)
        });
        let f = out
            .into_iter()
            .next()
            .expect("rank 0")
            .and_then(|x| x)
            .map_err(|e| CliError::Failure(e.to_string()))?
            .expect("rank 0 gets the frame");
        if corrected {
            for (i, fr) in f.frames.iter().enumerate() {
                let p = a.output.join(format!(
                    "display-{}-{}.png",
                    i as u32 / c.columns,
                    i as u32 % c.columns
                ));
                save(&p, c.width, c.height, fr, true)?;
            }
            save(&a.output.join("photo.png"), ww, wh, &f.photo, false)?;
        } else {
            save(
                &a.output.join("photo-uncorrected.png"),
                ww,
                wh,
                &f.photo,
                false,
            )?;
        }
    }
    eprintln!(
        "wrote {} display images and photo.png to {}",
        c.displays(),
        a.output.display()
    );
    Ok(())
}
