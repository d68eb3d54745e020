//! The third step: the inputs named in the [`Settings`] become the files to trace, in a fixed
//! order (named files as given, directories walked with their entries sorted by name), each with
//! how it is read (image, point list, standard input) and its place under an output directory.

use std::collections::BTreeSet;
use std::fs;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

use anyhow::{Context, Result};

use crate::settings::Settings;

/// Extensions read as images (decoded by content, so a wrong extension still decodes).
pub(crate) const IMAGE_EXTENSIONS: &[&str] = &[
    "png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "pnm", "pbm", "pgm", "ppm",
];
/// Most bytes read from standard input (`-`).
pub(crate) const MAX_STDIN_BYTES: u64 = 4 << 30;

/// Extensions read as point lists.
pub(crate) const POINT_LIST_EXTENSIONS: &[&str] = &["txt", "csv", "xy", "pts", "xyz", "ply"];

/// How an input file is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Image,
    PointList,
    /// Standard input (`-`): an image when the bytes start like one, else a point list.
    Stdin,
    /// A file with a point-list extension found in a walked directory: a point list when it
    /// parses as one with at least one point, else skipped with a warning (a `README.txt` among
    /// the scans).
    FoundText,
}

/// One input file, as found on the command line or in a walked directory.
#[derive(Clone, Debug)]
pub(crate) struct InputFile {
    pub path: PathBuf,
    pub kind: Kind,
    /// Its place under an output directory: the path below the walked directory it was found in,
    /// or, for a named file, below the deepest folder holding all named files
    /// ([`lay_out_named_files`]). `a/x.png` and `b/x.png` thus keep apart as `out/a/x.svg` and
    /// `out/b/x.svg`.
    pub layout: PathBuf,
}

/// An input that could not be traced, with the reason.
pub(crate) struct Failure {
    pub input: PathBuf,
    pub message: String,
}

/// Expands the command line's inputs into the files to trace, in a fixed order: named files as
/// given, directories walked with their entries sorted by name. Inputs that do not exist and
/// directories with nothing to trace become failures; other files in directories are skipped
/// with a warning, except the formats ridgeline writes (its own earlier outputs) and the output
/// and `--debug` folders when they lie inside a walked directory. Returns the files and whether
/// this is a batch (several inputs or a directory).
pub(crate) fn collect_inputs(
    settings: &Settings,
    warnings: &mut Vec<String>,
    failures: &mut Vec<Failure>,
) -> (Vec<InputFile>, bool) {
    let mut files = Vec::new();
    let mut named = Vec::new();
    let mut seen = BTreeSet::new();
    let mut batch = settings.inputs.len() > 1;
    // Folders ridgeline writes into are never walked as inputs.
    let own_folders: Vec<PathBuf> = [settings.output.as_deref(), settings.debug.as_deref()]
        .into_iter()
        .flatten()
        .filter_map(|path| fs::canonicalize(path).ok())
        .filter(|path| path.is_dir())
        .collect();
    for input in &settings.inputs {
        if input.as_os_str() == "-" {
            if seen.insert(input.clone()) {
                files.push(InputFile {
                    path: input.clone(),
                    kind: if settings.points {
                        Kind::PointList
                    } else {
                        Kind::Stdin
                    },
                    layout: PathBuf::from("stdin"),
                });
            }
            continue;
        }
        let metadata = match fs::metadata(input) {
            Ok(metadata) => metadata,
            Err(err) => {
                failures.push(Failure {
                    input: input.clone(),
                    message: format!("cannot read: {err}"),
                });
                continue;
            }
        };
        if !metadata.is_dir() {
            let kind = if settings.points || extension_is(input, POINT_LIST_EXTENSIONS) {
                Kind::PointList
            } else {
                Kind::Image
            };
            if seen.insert(input.clone()) {
                named.push(files.len());
                files.push(InputFile {
                    path: input.clone(),
                    kind,
                    layout: PathBuf::new(),
                });
            }
            continue;
        }
        batch = true;
        let mut found = Vec::new();
        let mut skipped = Vec::new();
        if let Err(err) = walk(input, &own_folders, &mut found, &mut skipped) {
            failures.push(Failure {
                input: input.clone(),
                message: format!("{err:#}"),
            });
            continue;
        }
        if !skipped.is_empty() {
            warnings.push(format!(
                "{}: skipped {} file(s) that are neither images nor point lists by extension, \
                 e.g. {}",
                input.display(),
                skipped.len(),
                skipped[0].display()
            ));
        }
        if found.is_empty() {
            failures.push(Failure {
                input: input.clone(),
                message: format!(
                    "no image or point-list files in this directory (extensions: {}, {})",
                    IMAGE_EXTENSIONS.join(" "),
                    POINT_LIST_EXTENSIONS.join(" ")
                ),
            });
            continue;
        }
        for path in found {
            let kind = if extension_is(&path, POINT_LIST_EXTENSIONS) {
                Kind::FoundText
            } else {
                Kind::Image
            };
            let layout = path.strip_prefix(input).unwrap_or(&path).to_path_buf();
            if seen.insert(path.clone()) {
                files.push(InputFile { path, kind, layout });
            }
        }
    }
    lay_out_named_files(&mut files, &named);
    (files, batch)
}

/// Gives the files named on the command line their place under an output directory (see
/// [`InputFile::layout`]): their paths below the deepest folder that holds them all, so that
/// `scans/a.png scans/b.png` become `a.svg b.svg` and `a/x.png b/x.png` become `a/x.svg b/x.svg`.
/// Paths that climb out with `..` keep only their file name.
fn lay_out_named_files(files: &mut [InputFile], named: &[usize]) {
    fn parts(path: &Path) -> Option<Vec<Component<'_>>> {
        let kept: Vec<Component> = path
            .components()
            .filter(|c| *c != Component::CurDir)
            .collect();
        (!kept.contains(&Component::ParentDir)).then_some(kept)
    }
    let mut common: Option<Vec<Component>> = None;
    for &i in named {
        let Some(mut folder) = parts(&files[i].path) else {
            continue;
        };
        folder.pop();
        common = Some(match common {
            None => folder,
            Some(prefix) => prefix
                .into_iter()
                .zip(folder)
                .take_while(|(a, b)| a == b)
                .map(|(a, _)| a)
                .collect(),
        });
    }
    let depth = common.map_or(0, |prefix| prefix.len());
    for &i in named {
        let path = &files[i].path;
        files[i].layout = match parts(path) {
            Some(kept) => kept[depth.min(kept.len().saturating_sub(1))..]
                .iter()
                .collect(),
            None => PathBuf::from(path.file_name().unwrap_or(path.as_os_str())),
        };
    }
}

/// Walks `dir` recursively, entries sorted by name, collecting files with an image or point-list
/// extension into `found` and the others into `skipped`. Hidden entries (names starting with
/// '.'), the formats ridgeline writes and the folders in `own_folders` (canonical paths) are
/// passed over; symbolic links to directories are not followed (no cycles).
fn walk(
    dir: &Path,
    own_folders: &[PathBuf],
    found: &mut Vec<PathBuf>,
    skipped: &mut Vec<PathBuf>,
) -> Result<()> {
    let mut entries = fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("cannot list {}", dir.display()))?;
    entries.sort_by_key(|entry| entry.file_name());
    for entry in entries {
        if entry.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        let path = entry.path();
        let file_type = entry
            .file_type()
            .with_context(|| format!("cannot read {}", path.display()))?;
        if file_type.is_dir() {
            let own = fs::canonicalize(&path).is_ok_and(|real| own_folders.contains(&real));
            if !own {
                walk(&path, own_folders, found, skipped)?;
            }
        } else if file_type.is_symlink() && path.is_dir() {
            continue;
        } else if extension_is(&path, IMAGE_EXTENSIONS)
            || extension_is(&path, POINT_LIST_EXTENSIONS)
        {
            found.push(path);
        } else if !extension_is(&path, &["svg", "json"]) {
            skipped.push(path);
        }
    }
    Ok(())
}

/// Whether `path`'s extension is one of `extensions` (case-insensitive).
pub(crate) fn extension_is(path: &Path, extensions: &[&str]) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| extensions.iter().any(|x| x.eq_ignore_ascii_case(e)))
}

/// Reads all of standard input, refusing more than [`MAX_STDIN_BYTES`].
pub(crate) fn read_stdin() -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(MAX_STDIN_BYTES + 1)
        .read_to_end(&mut bytes)
        .context("cannot read standard input")?;
    if bytes.len() as u64 > MAX_STDIN_BYTES {
        anyhow::bail!(
            "standard input holds more than {} GiB; save it to a file first",
            MAX_STDIN_BYTES >> 30
        );
    }
    Ok(bytes)
}

/// How bytes from standard input are read: as an image when they start like one (the decoder
/// sniffs the format the same way for files), else as a point list when they are text or PLY.
pub(crate) fn sniff(bytes: &[u8]) -> Kind {
    let ply = bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n");
    if ply || (image::guess_format(bytes).is_err() && std::str::from_utf8(bytes).is_ok()) {
        Kind::PointList
    } else {
        Kind::Image
    }
}
