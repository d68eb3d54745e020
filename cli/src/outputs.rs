//! The fourth step: where each input's output goes (see `--output`: beside the input, a file,
//! a directory keeping the inputs' layout, or stdout), checked before anything is traced so that
//! no output replaces an input; and writing them: the document of each format (SVG, JSON,
//! `.xyt`, ISO/IEC 19794-2), the `--debug` pictures, every file atomically.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use ridgeline::curves::{fit_beziers, fit_edges};
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, Backdrop};
use ridgeline::export::Features;
use ridgeline::minutiae::{minutiae, MinutiaeOptions};
use ridgeline::strokes::{strokes, StrokeOptions};
use ridgeline::CurveGraph3d;

use crate::flags::Format;
use crate::inputs::{extension_is, InputFile, Kind};
use crate::settings::{Settings, UsageError};

/// Every job of a run, and what no job's later pages may write over.
pub struct Plan {
    pub jobs: Vec<Job>,
    /// What later pages of a multi-page input (named inside the job, `name.pN.svg`) must not
    /// write over: the inputs, by identity, and the outputs planned for the other inputs.
    pub reserved: Reserved,
}

/// Plans the outputs of `files` (found by [`crate::inputs::collect_inputs`]; `batch` when
/// several inputs or a directory were named): each file's destination and `--debug` folder,
/// creating the output directory. Refuses, before anything is traced, a plan that would write
/// over an input.
pub fn plan(settings: &Settings, files: Vec<InputFile>, batch: bool) -> Result<Plan> {
    let destinations = plan_outputs(settings, &files, batch, settings.format)?;
    let several = files.len() > 1;
    let jobs: Vec<Job> = files
        .into_iter()
        .zip(destinations)
        .map(|(file, (destination, create_folder))| {
            // One input draws into DIR itself; several into DIR/<output path without its
            // extension>, unique because output paths are.
            let debug = settings.debug.as_ref().map(|dir| match &destination {
                Destination::File(path) if several => {
                    dir.join(debug_folder(settings.output.as_deref(), path))
                }
                _ => dir.clone(),
            });
            Job {
                input: file.path,
                kind: file.kind,
                destination,
                create_folder,
                debug,
            }
        })
        .collect();
    let reserved = Reserved::of(&jobs);
    refuse_overwriting_inputs(&jobs, &reserved)?;
    Ok(Plan { jobs, reserved })
}

/// Where one output goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Destination {
    Stdout,
    File(PathBuf),
}

/// One input and where its output goes.
#[derive(Debug)]
pub struct Job {
    pub input: PathBuf,
    pub kind: Kind,
    pub destination: Destination,
    /// The destination lies in a subfolder of the output directory, created when writing.
    pub create_folder: bool,
    /// Where `--debug` pictures go.
    pub debug: Option<PathBuf>,
}

/// Files no page output may replace (see [`Plan::reserved`]).
#[derive(Default)]
pub struct Reserved {
    inputs: BTreeMap<FileId, PathBuf>,
    outputs: BTreeSet<PathBuf>,
}

impl Reserved {
    fn of(jobs: &[Job]) -> Reserved {
        Reserved {
            inputs: jobs
                .iter()
                .filter(|job| job.input.as_os_str() != "-")
                .filter_map(|job| Some((file_id(&job.input)?, job.input.clone())))
                .collect(),
            outputs: jobs
                .iter()
                .filter_map(|job| match &job.destination {
                    Destination::File(path) => Some(path.clone()),
                    Destination::Stdout => None,
                })
                .collect(),
        }
    }

    /// The message refusing `path` when it is one of the inputs.
    fn overwrites_input(&self, path: &Path) -> Option<String> {
        let input = file_id(path).and_then(|id| self.inputs.get(&id))?;
        Some(format!(
            "{} is the input {}: ridgeline never writes over its inputs; choose another output \
             with -o",
            path.display(),
            input.display()
        ))
    }

    /// Refuses a page output that is an input or another input's planned output.
    pub fn check(&self, path: &Path) -> Result<()> {
        if let Some(message) = self.overwrites_input(path) {
            anyhow::bail!(message);
        }
        if self.outputs.contains(path) {
            anyhow::bail!(
                "{} is also the output of another input; give the inputs different names or \
                 an output directory",
                path.display()
            );
        }
        Ok(())
    }
}

/// Whether `-o path` names a directory whatever the number of inputs: it ends in a separator or
/// is an existing directory.
pub fn names_directory(path: &Path) -> bool {
    path.as_os_str()
        .to_string_lossy()
        .ends_with(std::path::is_separator)
        || path.is_dir()
}

/// Decides where each file's output goes (see `--output`), creating the output directory, and
/// whether its subfolder there must be created when it is written.
fn plan_outputs(
    settings: &Settings,
    files: &[InputFile],
    batch: bool,
    format: Format,
) -> Result<Vec<(Destination, bool)>> {
    let inputs: Vec<&Path> = files.iter().map(|file| file.path.as_path()).collect();
    let extension = format.extension();
    let Some(output) = &settings.output else {
        let folders: Vec<PathBuf> = inputs
            .iter()
            .map(|input| input.parent().unwrap_or(Path::new("")).to_path_buf())
            .collect();
        let paths = unique_paths(&inputs, &folders, extension);
        // Standard input has no path of its own to write beside: like a filter, it goes to
        // standard output.
        return Ok(files
            .iter()
            .zip(paths)
            .map(|(file, path)| match file.path.as_os_str() == "-" {
                true if files.len() == 1 => (Destination::Stdout, false),
                _ => (Destination::File(path), false),
            })
            .collect());
    };
    if output.as_os_str() == "-" {
        if batch || files.len() > 1 {
            return Err(UsageError(
                "-o - writes one input to stdout; give one input file, or an output directory"
                    .into(),
            )
            .into());
        }
        return Ok(vec![(Destination::Stdout, false); files.len()]);
    }
    if !(batch || names_directory(output)) {
        // One output file: its folder must exist (only an output directory is created).
        let folder = match output.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        if !folder.is_dir() {
            return Err(anyhow::anyhow!(
                "cannot write {}: {}",
                output.display(),
                missing_folder(folder)
            ));
        }
        return Ok(vec![
            (Destination::File(output.clone()), false);
            files.len()
        ]);
    }
    if output.exists() && !output.is_dir() {
        return Err(UsageError(format!(
            "{} is a file, but several inputs need an output directory",
            output.display()
        ))
        .into());
    }
    if !output.exists() && extension_is(output, &["svg", "json"]) {
        return Err(UsageError(format!(
            "several inputs need an output directory, not a file like {}",
            output.display()
        ))
        .into());
    }
    fs::create_dir_all(output)
        .with_context(|| format!("cannot create the output directory {}", output.display()))?;
    let folders: Vec<PathBuf> = files
        .iter()
        .map(|file| output.join(file.layout.parent().unwrap_or(Path::new(""))))
        .collect();
    Ok(unique_paths(&inputs, &folders, extension)
        .into_iter()
        .zip(&folders)
        .map(|(path, folder)| (Destination::File(path), folder != output))
        .collect())
}

/// Why `folder` cannot take a file: an ancestor that is a file, or the folder is missing.
pub fn missing_folder(folder: &Path) -> String {
    let blocking = folder
        .ancestors()
        .find(|a| !a.as_os_str().is_empty() && a.exists() && !a.is_dir());
    match blocking {
        Some(file) => format!("{} is a file, not a folder", file.display()),
        None => format!("folder {} does not exist", folder.display()),
    }
}

/// The `--debug` folder of one input in a batch: its output path below the output directory (or
/// its file name), without the extension.
fn debug_folder(output_dir: Option<&Path>, output: &Path) -> PathBuf {
    let below = output_dir
        .and_then(|dir| output.strip_prefix(dir).ok())
        .unwrap_or_else(|| Path::new(output.file_name().unwrap_or(output.as_os_str())));
    below.with_extension("")
}

/// A file's identity: device and inode where the platform has them (a hard link, a symbolic link
/// or `./x` is the same file), else its canonical path.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord)]
enum FileId {
    #[cfg(unix)]
    Inode(u64, u64),
    #[cfg(not(unix))]
    Path(PathBuf),
}

fn file_id(path: &Path) -> Option<FileId> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let metadata = fs::metadata(path).ok()?;
        Some(FileId::Inode(metadata.dev(), metadata.ino()))
    }
    #[cfg(not(unix))]
    {
        fs::canonicalize(path).ok().map(FileId::Path)
    }
}

/// A run never writes over one of its own inputs: every output file and `--debug` picture that
/// already exists is compared with the inputs (`reserved`) by identity, before anything is
/// traced. (One metadata read per path, so that a batch of thousands stays linear; the
/// `same-file` crate would hold every input open.)
fn refuse_overwriting_inputs(jobs: &[Job], reserved: &Reserved) -> Result<(), UsageError> {
    for job in jobs {
        let pictures = job.debug.iter().flat_map(|dir| {
            ridgeline::debug::PICTURE_NAMES
                .into_iter()
                .chain([ridgeline::debug::DECISIONS_PICTURE])
                .chain(ridgeline::debug::PRINT_PICTURE_NAMES)
                .map(|name| dir.join(name))
        });
        let outputs = match &job.destination {
            Destination::File(path) => Some(path.clone()),
            Destination::Stdout => None,
        };
        for path in outputs.into_iter().chain(pictures) {
            if let Some(message) = reserved.overwrites_input(&path) {
                return Err(UsageError(message));
            }
        }
    }
    Ok(())
}

/// Output paths `<folder>/<stem>.<extension>`, one per input in its folder, all different and
/// none equal to an input. Clashes are resolved deterministically (the result depends only on
/// the lists): inputs that share a name get their parent directory's name appended
/// (`page-scans.svg`), then their own extension (`page-scans-png.svg`), then a counter in input
/// order (`page-2.svg`).
fn unique_paths(inputs: &[&Path], folders: &[PathBuf], extension: &str) -> Vec<PathBuf> {
    let candidate = |i: usize, level: usize| -> PathBuf {
        let input = inputs[i];
        let stem = match input.as_os_str() == "-" {
            true => "stdin".into(),
            false => input
                .file_stem()
                .unwrap_or(input.as_os_str())
                .to_string_lossy(),
        };
        let mut base = stem.into_owned();
        if level >= 1 {
            if let Some(parent) = input.parent().and_then(Path::file_name) {
                base = format!("{base}-{}", parent.to_string_lossy());
            }
        }
        if level >= 2 {
            if let Some(own) = input.extension() {
                base = format!("{base}-{}", own.to_string_lossy());
            }
        }
        folders[i].join(base)
    };
    let mut levels = vec![0usize; inputs.len()];
    for _ in 0..2 {
        let paths: Vec<PathBuf> = (0..inputs.len())
            .map(|i| with_extension_added(candidate(i, levels[i]), extension))
            .collect();
        let mut count = BTreeMap::new();
        for path in &paths {
            *count.entry(path.clone()).or_insert(0usize) += 1;
        }
        let mut changed = false;
        for (path, level) in paths.iter().zip(&mut levels) {
            if count[path] > 1 {
                *level += 1;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Never overwrite an input, and never give two inputs the same output.
    let mut taken: BTreeSet<PathBuf> = inputs.iter().map(|p| p.to_path_buf()).collect();
    (0..inputs.len())
        .map(|i| {
            let base = candidate(i, levels[i]);
            let mut path = with_extension_added(base.clone(), extension);
            let mut counter = 2;
            while taken.contains(&path) {
                let mut numbered = base.clone().into_os_string();
                numbered.push(format!("-{counter}"));
                path = with_extension_added(numbered.into(), extension);
                counter += 1;
            }
            taken.insert(path.clone());
            path
        })
        .collect()
}

/// `base` with `.extension` appended (`Path::with_extension` would replace a dotted part of the
/// name, as in `page.v2`).
fn with_extension_added(base: PathBuf, extension: &str) -> PathBuf {
    let mut name = base.into_os_string();
    name.push(".");
    name.push(extension);
    name.into()
}

/// Where page `number` of an input goes: page 1 to `destination`, page N to
/// `<stem>.pN.<extension>` beside it.
pub fn page_destination(destination: &Destination, number: usize) -> Destination {
    match destination {
        Destination::File(path) if number > 1 => {
            let mut name = path.file_stem().unwrap_or(path.as_os_str()).to_os_string();
            name.push(format!(".p{number}"));
            if let Some(extension) = path.extension() {
                name.push(".");
                name.push(extension);
            }
            Destination::File(path.with_file_name(name))
        }
        other => other.clone(),
    }
}

/// Resolution of ISO/IEC 19794-2 records when neither `--dpi` nor the file gives one.
const DEFAULT_DPI: f64 = 500.0;

/// The output document of one traced graph (of an input read as `kind`): SVG over `backdrop`,
/// or JSON with `meta`; ISO records at `--dpi`, else `file_dpi`, else [`DEFAULT_DPI`], with the
/// 255 minutiae of highest quality when there are more (said in `warnings`).
#[allow(clippy::too_many_arguments)]
pub fn render(
    job: &Job,
    settings: &Settings,
    kind: Kind,
    trace: &ridgeline::Trace,
    backdrop: Option<Backdrop>,
    meta: JsonMeta,
    file_dpi: Option<f64>,
    warnings: &mut Vec<String>,
) -> Result<Vec<u8>> {
    let graph = &trace.graph;
    let binary = trace.binary.as_ref();
    // Strokes are cheap (one pass over the edge ends), so the JSON always lists them; the SVG
    // draws them on request.
    let chained = (settings.format == Format::Json || settings.strokes)
        .then(|| strokes(graph, &StrokeOptions::default()));
    // The foreground mask tells where the print ends; point lists have only the extent.
    // The fingerprint front end's minutiae are filtered inside its print; others come from the
    // graph and the mask.
    let wanted = settings.minutiae || matches!(settings.format, Format::Xyt | Format::Iso);
    let marks = wanted.then(|| match &trace.fingerprint {
        Some(print) => print.minutiae.clone(),
        None => minutiae(graph, binary, &MinutiaeOptions::default()),
    });
    Ok(match settings.format {
        Format::Xyt => {
            ridgeline::export::xyt::to_string(marks.as_deref().unwrap_or(&[]), graph.height)
                .into_bytes()
        }
        Format::Iso => {
            use ridgeline::export::iso19794::{best_for_record, to_bytes, MAX_MINUTIAE};
            let all = marks.as_deref().unwrap_or(&[]);
            // A record holds 255 minutiae; a matcher given more keeps those it trusts most,
            // so the record does too, and says so.
            let kept = best_for_record(all);
            if kept.len() < all.len() {
                warnings.push(format!(
                    "{} minutiae, more than the {MAX_MINUTIAE} an ISO/IEC 19794-2 record \
                     holds: wrote the {MAX_MINUTIAE} of highest quality (the JSON and .xyt \
                     outputs keep all {})",
                    all.len(),
                    all.len()
                ));
            }
            to_bytes(
                &kept,
                graph.width,
                graph.height,
                settings.dpi.or(file_dpi).unwrap_or(DEFAULT_DPI),
            )?
        }
        Format::Svg => {
            // Curves follow what is drawn: one list per stroke with --strokes, else per edge.
            let curves = settings.curves.map(|options| match &chained {
                Some(strokes) => strokes
                    .iter()
                    .map(|s| fit_beziers(&s.points, options.tolerance, options.corner_angle_deg))
                    .collect(),
                None => fit_edges(graph, &options),
            });
            let features = Features::default()
                .with_strokes(chained.as_deref())
                .with_minutiae(marks.as_deref())
                .with_curves(curves.as_deref());
            // A point list has no image to cover: the canvas fits the points.
            let svg_options = settings
                .svg
                .clone()
                .with_fit_canvas(kind == Kind::PointList);
            svg::to_string_with(graph, backdrop, &svg_options, &features).into_bytes()
        }
        Format::Ply => {
            ridgeline::export::polylines::to_ply(&CurveGraph3d::from_plane(graph)).into_bytes()
        }
        Format::Obj => {
            ridgeline::export::polylines::to_obj(&CurveGraph3d::from_plane(graph)).into_bytes()
        }
        Format::Json => {
            let meta = meta
                .with_source_path(job.input.to_string_lossy())
                .with_pretty(settings.pretty);
            // In the JSON, curves are per edge.
            let curves = settings.curves.map(|options| fit_edges(graph, &options));
            let features = Features::default()
                .with_strokes(chained.as_deref())
                .with_minutiae(marks.as_deref())
                .with_curves(curves.as_deref());
            json::to_string_with(graph, &meta, &features).into_bytes()
        }
    })
}

/// The output document of a point set in space: JSON with `z`, PLY or OBJ polylines (the caller
/// refuses the plane's formats first).
pub fn render_space(
    job: &Job,
    settings: &Settings,
    trace: &ridgeline::Trace3d,
    wall: std::time::Duration,
) -> Vec<u8> {
    use ridgeline::export::polylines::{to_obj, to_ply};
    match settings.format {
        Format::Ply => to_ply(&trace.graph).into_bytes(),
        Format::Obj => to_obj(&trace.graph).into_bytes(),
        _ => {
            let mut meta = JsonMeta::new(settings.params.clone())
                .with_source_path(job.input.to_string_lossy())
                .with_pretty(settings.pretty)
                .with_input("points3d");
            if settings.timings {
                meta = meta.with_timings(None, wall);
            }
            ridgeline::export::json::to_string_3d(trace, &meta).into_bytes()
        }
    }
}

/// Writes one output document of `job` to stdout or (atomically) to its file; returns where it
/// went, as the user should read it.
pub fn write_output(job: &Job, destination: &Destination, text: &[u8]) -> Result<String> {
    Ok(match destination {
        Destination::Stdout => {
            let mut stdout = std::io::stdout().lock();
            stdout.write_all(text).context("cannot write to stdout")?;
            stdout.flush().context("cannot write to stdout")?;
            "stdout".to_string()
        }
        Destination::File(path) => {
            if job.create_folder {
                if let Some(folder) = path.parent() {
                    fs::create_dir_all(folder).with_context(|| {
                        format!("cannot create the output folder {}", folder.display())
                    })?;
                }
            }
            write_atomically(path, text)?;
            path.display().to_string()
        }
    })
}

/// Writes the pictures of a trace recorded with its stages (the library's `*_with_stages`
/// entries) into `dir` (created if missing), each atomically, one at a time; the final picture is
/// the output's graph.
pub fn write_debug_pictures(
    gray: &ridgeline::GrayImage,
    trace: &ridgeline::Trace,
    dir: &Path,
) -> Result<()> {
    if let (Some(stages), Some(binary)) = (&trace.stages, &trace.binary) {
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the --debug folder {}", dir.display()))?;
        if let Some(decisions) = &trace.decisions {
            let png = ridgeline::debug::decisions_png(gray, binary, decisions)?;
            write_atomically(&dir.join(ridgeline::debug::DECISIONS_PICTURE), &png)
                .context("cannot write the --debug pictures")?;
        }
        if let Some(print) = &trace.fingerprint {
            for (name, png) in ridgeline::debug::print_pngs(gray, &print.analysis)? {
                write_atomically(&dir.join(name), &png)
                    .context("cannot write the --debug pictures")?;
            }
        }
        for picture in ridgeline::debug::stage_pngs(binary, stages, &trace.graph) {
            let (name, png) = picture?;
            write_atomically(&dir.join(name), &png).context("cannot write the --debug pictures")?;
        }
    }
    Ok(())
}

/// The operating system's reason inside an I/O error, without the paths that wrappers (such as
/// the temporary file's) add.
fn os_reason(err: &std::io::Error) -> String {
    let mut source: Option<&(dyn std::error::Error + 'static)> = Some(err);
    while let Some(current) = source {
        if let Some(code) = current
            .downcast_ref::<std::io::Error>()
            .and_then(std::io::Error::raw_os_error)
        {
            return std::io::Error::from_raw_os_error(code).to_string();
        }
        source = current.source();
    }
    err.kind().to_string()
}

/// Writes `bytes` to `path` atomically ([`replace_file`]). Errors name `path` and the reason,
/// never the temporary file.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        anyhow::bail!("cannot write {}: {}", path.display(), missing_folder(dir));
    }
    replace_file(path, bytes)
        .map_err(|err| anyhow::anyhow!("cannot write {}: {}", path.display(), os_reason(&err)))
}

/// Writes `bytes` to a temporary file beside `path`, then renames it over `path`: readers see the
/// old file or the new one, never a truncated one, and a failure leaves the old file as it was (and
/// no temporary file behind). The file is an ordinary one, readable as usual (mode 0644 less the
/// umask). The error is the operating system's, for the caller to name `path`.
fn replace_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write as _;
    use std::sync::atomic::{AtomicU64, Ordering};
    // Unique among this process's writes; `create_new` refuses a name another process holds.
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let (temp, mut file) = loop {
        let name = format!(
            ".ridgeline-{}-{}.tmp",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let temp = dir.join(name);
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o644);
        }
        match options.open(&temp) {
            Ok(file) => break (temp, file),
            Err(err) if err.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(err) => return Err(err),
        }
    };
    let written = file.write_all(bytes).and_then(|()| {
        drop(file);
        std::fs::rename(&temp, path)
    });
    if written.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clashing_names_are_resolved_deterministically() {
        let inputs = [
            Path::new("a/page.png"),
            Path::new("b/page.png"),
            Path::new("b/page.jpg"),
            Path::new("c/x.png"),
        ];
        let out = vec![PathBuf::from("out"); inputs.len()];
        let paths = unique_paths(&inputs, &out, "svg");
        let names: Vec<String> = paths
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["page-a.svg", "page-b-png.svg", "page-b-jpg.svg", "x.svg"]
        );
        let parents: Vec<PathBuf> = inputs
            .iter()
            .map(|p| p.parent().unwrap().to_path_buf())
            .collect();
        let next_to_input = unique_paths(&inputs, &parents, "svg");
        assert_eq!(next_to_input[0], Path::new("a/page.svg"));
        assert_eq!(next_to_input[1], Path::new("b/page-b-png.svg"));
        assert_eq!(next_to_input[3], Path::new("c/x.svg"));
        // An output never replaces an input.
        let own = unique_paths(&[Path::new("d/x.svg")], &[PathBuf::from("d")], "svg");
        assert_eq!(own[0], Path::new("d/x-2.svg"));
    }
}
