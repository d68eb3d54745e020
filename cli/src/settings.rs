//! The second step: the flags become one [`Settings`], validated, built once; nothing after this
//! step sees the flags. Parameters come from the flags in one place (`TryFrom<&Cli> for
//! Params`); the output format, the SVG and curve options and the warnings about flags that
//! change nothing are decided here too.

use std::fmt;
use std::path::{Path, PathBuf};

use ridgeline::curves::CurveOptions;
use ridgeline::export::svg::SvgOptions;
use ridgeline::{Params, RegionKind, Threshold};

use crate::flags::{Cli, DropoutMode, Format};
use crate::outputs::names_directory;

/// The formats written, for messages.
const OUTPUT_FORMATS: &str = "SVG (.svg), JSON (.json), NIST minutiae (.xyt), ISO/IEC 19794-2 \
     records (.ist, .iso19794) and polylines for 3D viewers (.ply, .obj)";

/// Everything a run needs, decided from the flags once.
pub struct Settings {
    /// The inputs as named: files, directories (walked), `-` for standard input.
    pub inputs: Vec<PathBuf>,
    /// `--points`: every named file is a point list, whatever its extension.
    pub points: bool,
    /// `-o`: a file, a directory, `-`, or none (beside each input).
    pub output: Option<PathBuf>,
    /// `--debug DIR`.
    pub debug: Option<PathBuf>,
    pub params: Params,
    pub format: Format,
    pub svg: SvgOptions,
    /// The SVG embeds the source image (not `--no-image`).
    pub embed_image: bool,
    /// `--pretty`.
    pub pretty: bool,
    /// `--timings`: seconds per stage in the JSON.
    pub timings: bool,
    /// `--strokes`.
    pub strokes: bool,
    /// `--minutiae` (or `--fingerprint`, `--enhance`).
    pub minutiae: bool,
    /// `--dpi`, for ISO/IEC 19794-2 records (else the file's, else a default).
    pub dpi: Option<f64>,
    /// `--curves` with its tolerance and corner angle.
    pub curves: Option<CurveOptions>,
    /// `--jobs`: files traced at once [default: one per core].
    pub threads: Option<usize>,
    /// `--quiet`.
    pub quiet: bool,
    /// Flags given that change nothing in the chosen format, as warnings for the run to print.
    pub ignored_flags: Vec<String>,
}

impl TryFrom<&Cli> for Settings {
    type Error = UsageError;

    fn try_from(cli: &Cli) -> Result<Settings, UsageError> {
        let mut params = Params::try_from(cli)?;
        if let Some(width) = cli.line_width.filter(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(UsageError(format!(
                "--line-width must be > 0 px, got {width}"
            )));
        }
        let curves = cli.curves.then(|| {
            let defaults = CurveOptions::default();
            CurveOptions {
                tolerance: cli.curve_tolerance.unwrap_or(defaults.tolerance),
                corner_angle_deg: cli.corner_angle.unwrap_or(defaults.corner_angle_deg),
            }
        });
        if let Some(options) = &curves {
            if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
                return Err(UsageError(format!(
                    "--curve-tolerance must be > 0 px, got {}",
                    options.tolerance
                )));
            }
            if !(options.corner_angle_deg >= 0.0 && options.corner_angle_deg <= 180.0) {
                return Err(UsageError(format!(
                    "--corner-angle must be in [0, 180] degrees, got {}",
                    options.corner_angle_deg
                )));
            }
        }
        let format = output_format(cli)?;
        // The ridges' width is written only in the JSON (and the decisions' picture is drawn
        // with `--debug`): other outputs skip measuring it.
        if let Some(print) = params.fingerprint.as_mut() {
            print.ridge_width = format == Format::Json || cli.debug.is_some();
        }
        Ok(Settings {
            inputs: cli.inputs.clone(),
            points: cli.points,
            output: cli.output.clone(),
            debug: cli.debug.clone(),
            params,
            format,
            svg: SvgOptions::default()
                .with_show_vertices(!cli.no_vertices)
                .with_stroke_width(cli.line_width)
                .with_show_widths(cli.width),
            embed_image: !cli.no_image,
            pretty: cli.pretty,
            timings: cli.timings,
            strokes: cli.strokes,
            minutiae: cli.minutiae || cli.fingerprint || cli.enhance.is_some(),
            dpi: cli.dpi,
            curves,
            threads: cli.jobs.map(usize::from),
            quiet: cli.quiet,
            ignored_flags: ignored_flags(cli, format),
        })
    }
}

/// A mistake in how the tool was called; `main` exits with status 2 for it.
#[derive(Debug)]
pub struct UsageError(pub String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// The one place where flags become parameters: start from the defaults (or the paper's values
/// with `--paper`), apply only the flags that were given, then let [`Params::validate`] check the
/// ranges.
impl TryFrom<&Cli> for Params {
    type Error = UsageError;

    fn try_from(cli: &Cli) -> Result<Params, UsageError> {
        let mut params = if cli.paper {
            Params::paper()
        } else {
            Params::default()
        };
        if cli.fingerprint || cli.enhance.is_some() {
            params.fingerprint = Params::fingerprint().fingerprint;
        }
        if let (Some(method), Some(print)) = (cli.enhance, params.fingerprint.as_mut()) {
            print.enhancement = method;
        }
        if let Some(method) = cli.binarize {
            params.front_end.threshold = method;
        }
        if let Some(level) = cli.threshold {
            params.front_end.threshold = Threshold::Fixed { level };
        }
        if cli.sauvola {
            params.front_end.threshold = Threshold::Sauvola {
                window: cli.window.unwrap_or(Threshold::DEFAULT_SAUVOLA_WINDOW),
                k: cli.sauvola_k.unwrap_or(Threshold::DEFAULT_SAUVOLA_K),
            };
        }
        if let Some(DropoutMode(dropout)) = cli.dropout {
            params.front_end.dropout = dropout;
        }
        set(&mut params.front_end.polarity, cli.polarity);
        set(&mut params.method.r_min_rule, cli.r_min_rule);
        set(&mut params.method.cluster_rule, cli.clusters);
        set(&mut params.fit.laplacian, cli.laplacian);
        fn set<T: Copy>(field: &mut T, flag: Option<T>) {
            if let Some(value) = flag {
                *field = value;
            }
        }
        set(&mut params.front_end.dropout_fraction, cli.dropout_fraction);
        set(&mut params.front_end.min_area, cli.min_area);
        set(&mut params.method.r_min_factor, cli.r_min_factor);
        set(&mut params.method.r_max_factor, cli.r_max_factor);
        set(&mut params.method.r_growth, cli.r_growth);
        set(&mut params.method.linearity, cli.linearity);
        set(&mut params.method.k, cli.k);
        set(&mut params.method.cluster_link, cli.cluster_link);
        set(&mut params.method.merge_span, cli.merge_span);
        set(&mut params.fit.smoothness, cli.smoothness);
        set(&mut params.fit.anchor_weight, cli.anchor_weight);
        set(
            &mut params.fit.weiszfeld_iterations,
            cli.weiszfeld_iterations,
        );
        set(&mut params.fit.spacing_factor, cli.spacing_factor);
        set(&mut params.front_end.limits.max_pixels, cli.max_pixels);
        set(&mut params.front_end.limits.max_side, cli.max_side);
        set(&mut params.front_end.limits.max_points, cli.max_points);
        set(&mut params.front_end.limits.max_pages, cli.max_pages);
        if cli.no_arms_test {
            params.method.arms_test = false;
        }
        if cli.arms_test {
            params.method.arms_test = true;
        }
        if cli.no_cleanup {
            params.finish.cleanup = false;
        }
        if cli.cleanup {
            params.finish.cleanup = true;
        }
        if cli.no_subpixel {
            params.front_end.subpixel = false;
        }
        if cli.subpixel {
            params.front_end.subpixel = true;
        }
        if cli.no_valleys {
            params.front_end.valleys = false;
        }
        if cli.valleys {
            params.front_end.valleys = true;
        }
        if cli.no_reverse_grounds {
            params.front_end.reverse_grounds = false;
        }
        if cli.reverse_grounds {
            params.front_end.reverse_grounds = true;
        }
        for name in &cli.keep_regions {
            let kinds: Vec<RegionKind> = if name == "all" {
                RegionKind::ALL.to_vec()
            } else {
                match RegionKind::ALL.iter().find(|k| k.name() == name) {
                    Some(&kind) => vec![kind],
                    None => {
                        let names: Vec<&str> = RegionKind::ALL.iter().map(|k| k.name()).collect();
                        return Err(UsageError(format!(
                            "--keep-regions: unknown kind '{name}'; use {} or all",
                            names.join(", ")
                        )));
                    }
                }
            };
            for kind in kinds {
                if !params.front_end.keep_regions.contains(&kind) {
                    params.front_end.keep_regions.push(kind);
                }
            }
        }
        params.front_end.keep_regions.sort_unstable();
        if cli.no_skeleton {
            params.finish.skeleton = false;
        }
        if cli.skeleton {
            params.finish.skeleton = true;
        }
        params.validate().map_err(|err| match err {
            ridgeline::Error::InvalidParam { field, reason } => {
                UsageError(format!("{} {reason}", flag_of(field)))
            }
            other => UsageError(other.to_string()),
        })?;
        Ok(params)
    }
}

/// The flag that sets a [`Params`] field, as named by [`Params::validate`]'s errors and by the
/// library's limit errors.
pub(crate) fn flag_of(field: &str) -> String {
    match field {
        "threshold.window" => "--window".into(),
        "threshold.k" => "--sauvola-k".into(),
        other => format!(
            "--{}",
            other.trim_start_matches("limits.").replace('_', "-")
        ),
    }
}

/// `err` as the command line reports it, each cause after the one before as `{err:#}` writes
/// them, except that a limit of the library, which names its [`Params`] field, names the flag
/// that raises it.
pub(crate) fn describe(err: &anyhow::Error) -> String {
    err.chain()
        .map(|cause| match cause.downcast_ref::<ridgeline::Error>() {
            Some(ridgeline::Error::Limit {
                what,
                actual,
                limit,
                field,
            }) => ridgeline::Error::limit_sentence(
                what,
                actual,
                limit,
                &format!("it with {}", flag_of(field)),
            ),
            _ => cause.to_string(),
        })
        .collect::<Vec<_>>()
        .join(": ")
}

/// The output format: `--format`, else the `-o` file's extension, else SVG. An `-o` file whose
/// extension is not one ridgeline writes, or that contradicts `--format`, is a usage error: it
/// would otherwise get SVG text under a name that promises something else.
fn output_format(cli: &Cli) -> Result<Format, UsageError> {
    let file = cli
        .output
        .as_deref()
        .filter(|path| path.as_os_str() != "-" && !names_directory(path));
    let from_extension = match file.and_then(Path::extension) {
        None => None,
        Some(extension) => {
            let lower = extension.to_string_lossy().to_ascii_lowercase();
            match lower.as_str() {
                "svg" => Some(Format::Svg),
                "json" => Some(Format::Json),
                "xyt" => Some(Format::Xyt),
                "ist" | "iso19794" => Some(Format::Iso),
                "ply" => Some(Format::Ply),
                "obj" => Some(Format::Obj),
                _ => {
                    return Err(UsageError(format!(
                        "-o {}: ridgeline writes {OUTPUT_FORMATS}, not .{lower} (an output \
                         without an extension gets --format, or svg)",
                        cli.output.as_deref().unwrap_or(Path::new("")).display()
                    )))
                }
            }
        }
    };
    match (cli.format, from_extension) {
        (Some(flag), Some(extension)) if flag != extension => Err(UsageError(format!(
            "--format {} contradicts -o {}",
            flag.extension(),
            cli.output.as_deref().unwrap_or(Path::new("")).display()
        ))),
        (Some(flag), _) => Ok(flag),
        (None, Some(extension)) => Ok(extension),
        (None, None) => Ok(Format::Svg),
    }
}

/// Warnings for the flags given that change nothing in the chosen format.
fn ignored_flags(cli: &Cli, format: Format) -> Vec<String> {
    let (given, changes): (Vec<&str>, &str) = match format {
        Format::Json => (
            [
                (cli.no_image, "--no-image"),
                (cli.no_vertices, "--no-vertices"),
                (cli.line_width.is_some(), "--line-width"),
                (cli.width, "--width"),
                (cli.strokes, "--strokes"),
            ]
            .into_iter()
            .filter_map(|(on, flag)| on.then_some(flag))
            .collect(),
            "change only the SVG (the JSON always holds every width and the strokes)",
        ),
        Format::Svg => (
            [(cli.pretty, "--pretty"), (cli.timings, "--timings")]
                .into_iter()
                .filter_map(|(on, flag)| on.then_some(flag))
                .collect(),
            "change only the JSON",
        ),
        Format::Xyt | Format::Iso => (
            [
                (cli.pretty, "--pretty"),
                (cli.timings, "--timings"),
                (cli.strokes, "--strokes"),
                (cli.width, "--width"),
                (cli.curves, "--curves"),
            ]
            .into_iter()
            .filter_map(|(on, flag)| on.then_some(flag))
            .collect(),
            "change nothing in a minutiae file",
        ),
        Format::Ply | Format::Obj => (
            [
                (cli.pretty, "--pretty"),
                (cli.timings, "--timings"),
                (cli.strokes, "--strokes"),
                (cli.width, "--width"),
                (cli.curves, "--curves"),
                (cli.minutiae, "--minutiae"),
            ]
            .into_iter()
            .filter_map(|(on, flag)| on.then_some(flag))
            .collect(),
            "change nothing in a polyline file",
        ),
    };
    if given.is_empty() {
        return Vec::new();
    }
    let changes = if given.len() == 1 {
        changes.replacen("change ", "changes ", 1)
    } else {
        changes.replacen("changes ", "change ", 1)
    };
    vec![format!(
        "{} {changes}; writing {}",
        given.join(", "),
        format.extension().to_uppercase()
    )]
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;
    use ridgeline::{ClusterRule, LaplacianRule, Polarity, RMinRule};

    fn parse(args: &[&str]) -> Cli {
        Cli::try_parse_from(std::iter::once("ridgeline").chain(args.iter().copied()))
            .expect("valid command line")
    }

    #[test]
    fn a_print_measures_its_ridge_width_only_for_the_json() {
        let ridge_width = |args: &[&str]| {
            let settings = Settings::try_from(&parse(args)).expect("valid");
            settings.params.fingerprint.expect("a print").ridge_width
        };
        assert!(!ridge_width(&["--fingerprint", "a.png", "-o", "a.xyt"]));
        assert!(!ridge_width(&["--fingerprint", "a.png", "-o", "a.svg"]));
        assert!(ridge_width(&["--fingerprint", "a.png", "-o", "a.json"]));
        assert!(ridge_width(&["--fingerprint", "a.png", "--format", "json"]));
        assert!(ridge_width(&[
            "--fingerprint",
            "a.png",
            "-o",
            "a.svg",
            "--debug",
            "d"
        ]));
    }

    #[test]
    fn no_flags_give_the_default_parameters() {
        let params = Params::try_from(&parse(&["a.png"])).expect("valid");
        assert_eq!(params, Params::default());
        let paper = Params::try_from(&parse(&["--paper", "a.png"])).expect("valid");
        assert_eq!(paper, Params::paper());
    }

    #[test]
    fn given_flags_override_the_preset() {
        let cli = parse(&[
            "--paper",
            "--r-min-factor",
            "7",
            "--merge-span",
            "3",
            "--k",
            "8",
            "--sauvola",
            "--window",
            "15",
            "--polarity",
            "light",
            "--dropout",
            "on",
            "--max-pixels",
            "1000",
            "--no-arms-test",
            "a.png",
        ]);
        let params = Params::try_from(&cli).expect("valid");
        assert_eq!(params.method.r_min_rule, RMinRule::Spacing);
        assert_eq!(params.method.cluster_rule, ClusterRule::EqualDistance);
        assert_eq!(params.fit.laplacian, LaplacianRule::Uniform);
        assert_eq!(params.method.r_min_factor, 7.0);
        assert_eq!(params.method.merge_span, 3.0);
        assert_eq!(params.method.k, 8);
        assert_eq!(
            params.front_end.threshold,
            Threshold::Sauvola {
                window: 15,
                k: Threshold::DEFAULT_SAUVOLA_K
            }
        );
        assert_eq!(params.front_end.polarity, Polarity::LightInk);
        assert_eq!(params.front_end.dropout, Some(true));
        assert_eq!(params.front_end.limits.max_pixels, 1000);
        assert!(!params.method.arms_test);
        // Untouched fields keep the paper's values.
        assert_eq!(
            params.method.r_max_factor,
            Params::paper().method.r_max_factor
        );
        assert_eq!(params.fit.anchor_weight, Params::paper().fit.anchor_weight);
    }

    #[test]
    fn every_rule_of_the_paper_preset_can_be_given_back() {
        let params = Params::try_from(&parse(&[
            "--paper",
            "--r-min-rule",
            "width",
            "--r-min-factor",
            "1",
            "--r-max-factor",
            "3",
            "--arms-test",
            "--clusters",
            "non-linear",
            "--merge-span",
            "2",
            "--cleanup",
            "--laplacian",
            "held",
            "--anchor-weight",
            "10",
            "--skeleton",
            "--subpixel",
            "--valleys",
            "--reverse-grounds",
            "a.png",
        ]))
        .expect("valid");
        assert_eq!(params, Params::default());
        let grid = Params::try_from(&parse(&["--no-subpixel", "a.png"])).expect("valid");
        assert!(!grid.front_end.subpixel);
        let filled = Params::try_from(&parse(&["--no-valleys", "a.png"])).expect("valid");
        assert!(!filled.front_end.valleys);
        let banner = Params::try_from(&parse(&["--no-reverse-grounds", "a.png"])).expect("valid");
        assert!(!banner.front_end.reverse_grounds);
        let node_graph = Params::try_from(&parse(&["--no-skeleton", "a.png"])).expect("valid");
        assert!(!node_graph.finish.skeleton);
        let back = Params::try_from(&parse(&["--no-skeleton", "--skeleton", "a.png"])).expect("ok");
        assert!(back.finish.skeleton);
        // The last of a flag and its negation wins.
        let off = Params::try_from(&parse(&["--cleanup", "--no-cleanup", "a.png"])).expect("valid");
        assert!(!off.finish.cleanup);
        let on =
            Params::try_from(&parse(&["--no-arms-test", "--arms-test", "a.png"])).expect("valid");
        assert!(on.method.arms_test);
    }

    #[test]
    fn keep_regions_takes_kinds_and_all_and_refuses_others() {
        use ridgeline::RegionKind;
        let none = Params::try_from(&parse(&["a.png"])).expect("valid");
        assert!(none.front_end.keep_regions.is_empty());
        let some = Params::try_from(&parse(&["--keep-regions", "frame,halftone", "a.png"]))
            .expect("valid");
        assert_eq!(
            some.front_end.keep_regions,
            vec![RegionKind::Halftone, RegionKind::Frame]
        );
        let all = Params::try_from(&parse(&["--keep-regions", "all", "a.png"])).expect("valid");
        assert_eq!(all.front_end.keep_regions, RegionKind::ALL.to_vec());
        let bad = Params::try_from(&parse(&["--keep-regions", "photo", "a.png"]));
        assert!(bad.is_err_and(|e| e.0.contains("unknown kind 'photo'")));
    }

    #[test]
    fn out_of_range_parameters_are_usage_errors() {
        assert!(Params::try_from(&parse(&["--linearity", "1.5", "a.png"])).is_err());
        assert!(Params::try_from(&parse(&["--k", "1", "a.png"])).is_err());
        assert!(Params::try_from(&parse(&["--dropout-fraction", "2", "a.png"])).is_err());
        assert!(Cli::try_parse_from(["ridgeline", "--window", "9", "a.png"]).is_err());
        assert!(Cli::try_parse_from(["ridgeline", "--threshold", "300", "a.png"]).is_err());
        assert!(Cli::try_parse_from(["ridgeline", "--threshold", "9", "--sauvola", "a"]).is_err());
    }
}
