//! The one check of every subcommand's outputs, made before any work: the extension is
//! one the command writes, the path is not a folder, its folder exists and takes new
//! files. A failed check is bad input (exit code 2) in one line naming the option and
//! the path, so a long render never ends in "cannot write".

use crate::error::CliError;
use irradia_core::io::Format;
use std::path::{Path, PathBuf};

/// An image output (`-o`): .png, .exr or .pfm, in a folder that exists.
pub fn check_image(option: &str, path: &Path) -> Result<Format, CliError> {
    if path.is_dir() {
        return Err(CliError::Input(format!(
            "{option} {}: is a folder; give an image file name in it",
            path.display()
        )));
    }
    let format = Format::from_path(path).map_err(|_| {
        CliError::Input(format!(
            "{option} {}: unsupported image extension (use .png, .exr or .pfm)",
            path.display()
        ))
    })?;
    check_writable(option, path)?;
    Ok(format)
}

/// A data output (a report, a mesh, a table): one of `extensions` (lower case, without
/// the dot), in a folder that exists.
pub fn check_file(option: &str, path: &Path, extensions: &[&str]) -> Result<(), CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    if !ext.as_deref().is_some_and(|e| extensions.contains(&e)) {
        let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
        return Err(CliError::Input(format!(
            "{option} {}: unsupported extension (use {})",
            path.display(),
            list.join(" or ")
        )));
    }
    check_writable(option, path)
}

/// An output folder (`-o DIR` of `wall` and `bench parallel`): created now, with its
/// parents, if missing; an existing file of that name, or a folder that cannot be
/// created or written, is bad input.
pub fn prepare_folder(option: &str, dir: &Path) -> Result<(), CliError> {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::Input(format!(
            "{option} {}: is a file, not a folder",
            dir.display()
        )));
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        CliError::Input(format!(
            "{option} {}: cannot create the folder: {e}",
            dir.display()
        ))
    })?;
    probe(option, dir, dir)
}

/// The path is not a folder; its folder exists and takes new files.
fn check_writable(option: &str, path: &Path) -> Result<(), CliError> {
    if path.is_dir() {
        return Err(CliError::Input(format!(
            "{option} {}: is a folder, not a file",
            path.display()
        )));
    }
    let dir = folder_of(path);
    if !dir.is_dir() {
        return Err(CliError::Input(format!(
            "{option} {}: folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    probe(option, path, &dir)
}

/// The folder a file is written into ("." for a bare name).
pub fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Creates and removes a file in `dir` (outputs themselves are written atomically later).
fn probe(option: &str, path: &Path, dir: &Path) -> Result<(), CliError> {
    let probe = dir.join(format!(".irradia-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(CliError::Input(format!(
            "{option} {}: cannot write in {}: {e}",
            path.display(),
            dir.display()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(r: Result<impl std::fmt::Debug, CliError>) -> String {
        match r {
            Err(CliError::Input(m)) => m,
            other => panic!("expected bad input, got {other:?}"),
        }
    }

    #[test]
    fn images_need_a_known_extension_and_an_existing_folder() {
        let dir = tempfile::tempdir().unwrap();
        let ok = dir.path().join("a.exr");
        assert_eq!(check_image("-o", &ok).unwrap(), Format::Exr);
        let m = input(check_image("-o", &dir.path().join("r.jpg")));
        assert!(
            m.starts_with("-o ") && m.contains("r.jpg") && m.contains(".png"),
            "{m}"
        );
        let m = input(check_image("-o", &dir.path().join("no/such/x.png")));
        assert!(m.contains("does not exist") && !m.contains('\n'), "{m}");
        // The path once, not twice.
        assert_eq!(m.matches("x.png").count(), 1, "{m}");
        let m = input(check_image("-o", dir.path()));
        assert!(m.contains("is a folder"), "{m}");
    }

    #[test]
    fn data_files_need_one_of_their_extensions() {
        let dir = tempfile::tempdir().unwrap();
        check_file("--report", &dir.path().join("r.JSON"), &["json"]).unwrap();
        let m = input(check_file(
            "--mesh-out",
            &dir.path().join("m.obj"),
            &["ply"],
        ));
        assert!(m.contains("use .ply"), "{m}");
    }

    #[test]
    fn folders_are_created_but_a_file_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path().join("x/y");
        prepare_folder("-o", &d).unwrap();
        assert!(d.is_dir());
        let f = dir.path().join("f");
        std::fs::write(&f, b"").unwrap();
        assert!(input(prepare_folder("-o", &f)).contains("is a file"));
    }
}
