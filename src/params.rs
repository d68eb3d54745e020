//! Every tunable of the pipeline in one place, with the paper's symbol and unit.
//!
//! The defaults are the values that measure best on pixel images (docs/design.md, "Adaptations to
//! pixel images", and the quality benchmark); [`Params::paper`] gives the paper's own values so the
//! two can be compared.

use serde::{Deserialize, Serialize};

/// How gray levels become ink and paper.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", tag = "method")]
pub enum Threshold {
    /// Otsu's global level where it separates ink from paper all over the image, the local
    /// threshold ([`Threshold::Local`]) where the light or the contrast varies across it
    /// (docs/design.md, "The front end"). The default.
    Auto,
    /// Otsu's global threshold, wherever the light.
    Otsu,
    /// The local threshold: halfway between the darkest and lightest levels of blocks of about
    /// six stroke widths (the width measured on the image); blocks without strokes keep their
    /// own paper level and their neighbours' offset from paper; interpolated between block
    /// centers.
    Local,
    /// A fixed gray level 0-255; pixels darker than or equal to it are ink (for dark ink).
    Fixed {
        /// The level.
        level: u8,
    },
    /// Sauvola's adaptive threshold for unevenly lit scans.
    Sauvola {
        /// Side of the square window in pixels (odd). Default value:
        /// [`Threshold::DEFAULT_SAUVOLA_WINDOW`] (31).
        window: u32,
        /// Sensitivity `k`. Default value: [`Threshold::DEFAULT_SAUVOLA_K`] (0.2).
        k: f64,
    },
}

impl Threshold {
    /// Sauvola's window when none is given (the command line's `--sauvola` without `--window`),
    /// px.
    pub const DEFAULT_SAUVOLA_WINDOW: u32 = 31;
    /// Sauvola's `k` when none is given (`--sauvola` without `--sauvola-k`).
    pub const DEFAULT_SAUVOLA_K: f64 = 0.2;
}

/// Which side of the threshold is ink. Written `auto`, `dark` and `light`, as the command line
/// spells them (`darkink` and `lightink` are still read).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Polarity {
    /// Decide from stroke evidence: ink is the side made of strokes (thinner than the other
    /// side), paper the side that fills the border; dark when the evidence is weak, with a
    /// warning (docs/design.md, "The front end"). The default.
    Auto,
    /// Dark strokes on light paper.
    #[serde(rename = "dark", alias = "darkink")]
    DarkInk,
    /// Light strokes (ridges) on a dark background.
    #[serde(rename = "light", alias = "lightink")]
    LightInk,
}

/// How §3.1 chooses the smallest disk radius `r_min` ([`MethodParams::r_min_rule`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RMinRule {
    /// One local stroke width: `r_min = max(3 Dis_ave, r_min_factor · w_loc)`, where `w_loc` is
    /// the stroke width around the disk's center (docs/design.md, adaptation 3). The default.
    StrokeWidth,
    /// The paper's rule: `r_min = r_min_factor · Dis_ave` (§3.1, 10 `Dis_ave` in §4).
    Spacing,
}

/// Which nodes §3.2 groups into clusters, the non-linear regions that §3.3 merges
/// ([`MethodParams::cluster_rule`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClusterRule {
    /// Non-linear nodes only, joined by edges shorter than `cluster_link · r_min`; linear nodes
    /// belong to no cluster (docs/design.md, adaptation 8). The default.
    NonLinear,
    /// The paper's rule as written: edges shorter than `cluster_link · r_min` weigh 0, others
    /// their length; nodes at the same shortest distance from a root form one cluster (§3.2).
    EqualDistance,
}

/// The smoothness term `L` of Eq. (4) ([`FitParams::laplacian`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LaplacianRule {
    /// Rows `q_i - (q_a + q_b) / 2` for degree-2 nodes only: junctions and endpoints are held by
    /// their data term alone (docs/design.md, adaptation 12). The default.
    Held,
    /// The paper's uniform graph Laplacian over every node (§3.4), which pulls junctions and
    /// curves inward.
    Uniform,
}

/// Bounds on what one input may make the library allocate.
///
/// Decoding is refused from the image header beyond `max_pixels` or `max_side`. Tracing needs at
/// most about 450 bytes per foreground point plus 6 bytes per image pixel (peak RSS measured on
/// 12-megapixel pages, see `docs/bad-input.md`), and `max_points` is checked before any per-point
/// array is allocated, so the three limits bound the memory of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Limits {
    /// Largest image, in pixels (width x height), that will be decoded. Default value:
    /// [`Limits::DEFAULT_MAX_PIXELS`] (100 megapixels).
    pub max_pixels: u64,
    /// Largest image side in pixels. Default value: [`Limits::DEFAULT_MAX_SIDE`] (65 535).
    pub max_side: u32,
    /// Largest number of foreground points traced. Default value:
    /// [`Limits::DEFAULT_MAX_POINTS`] (50 million).
    pub max_points: u64,
    /// Largest number of pages (image file directories) of a multi-page TIFF; a file with more is
    /// refused before any page is decoded. Pages are decoded one at a time, each within the other
    /// limits. Default value: [`Limits::DEFAULT_MAX_PAGES`] (1000).
    #[serde(default = "default_max_pages")]
    pub max_pages: u64,
}

fn default_confirmed_share() -> f64 {
    FingerprintParams::default().confirmed_share
}

fn default_max_pages() -> u64 {
    Limits::DEFAULT_MAX_PAGES
}

impl Limits {
    /// Default of [`Limits::max_pixels`].
    pub const DEFAULT_MAX_PIXELS: u64 = 100_000_000;
    /// Default of [`Limits::max_side`].
    pub const DEFAULT_MAX_SIDE: u32 = 65_535;
    /// Default of [`Limits::max_points`].
    pub const DEFAULT_MAX_POINTS: u64 = 50_000_000;
    /// Default of [`Limits::max_pages`].
    pub const DEFAULT_MAX_PAGES: u64 = 1000;
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_pixels: Self::DEFAULT_MAX_PIXELS,
            max_side: Self::DEFAULT_MAX_SIDE,
            max_points: Self::DEFAULT_MAX_POINTS,
            max_pages: Self::DEFAULT_MAX_PAGES,
        }
    }
}

/// Largest [`FitParams::weiszfeld_iterations`]: more would only cost time (the medians converge in
/// far fewer).
pub const MAX_WEISZFELD_ITERATIONS: usize = 1000;

/// The fingerprint front end's contextual enhancement (docs/fingerprints.md, "Enhancement").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Enhancement {
    /// An even Gabor filter per block, tuned to its ridge orientation and period (Hong, Wan and
    /// Jain; pyfing's GBFEN). The default.
    #[default]
    Gabor,
    /// Oriented smoothing (SourceAFIS's method): an average along the ridge compared with its
    /// mean across one ridge period.
    Smoothing,
}

/// The fingerprint front end's tunables ([`Params::fingerprint`]; docs/fingerprints.md). The
/// defaults are pyfing's values for 500 dpi prints where it has one.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FingerprintParams {
    /// Side of the blocks of the segmentation, orientation, period and filter, px. Default value: 8.
    pub block: u32,
    /// Gaussian blur before the gradients and the x-signature, px. Default value: 1.
    pub gradient_sigma: f64,
    /// A block is print where its mean gradient magnitude reaches this fraction of the image's
    /// 95th percentile (pyfing's GMFS). Default value: 0.2.
    pub segment_threshold: f64,
    /// After the enhancement, a block stays print only where the Gabor response's root mean
    /// square, averaged over 3 x 3 blocks of the print, reaches this fraction of its 95th
    /// percentile over the print: the filter tuned to the ridges answers strongly to them and
    /// weakly to noise, which the gradient magnitude cannot tell from ridges. 0 keeps the
    /// gradient segmentation. Default value: 0.2.
    pub response_threshold: f64,
    /// A block of the print shows no ridges where the F ratio of its pixels grouped in rows along
    /// the ridges (the variance between the rows' means over the variance of one row's mean,
    /// within one ridge period across and 1.5 along, at the best of 12 orientations) is below
    /// this and its mean gray sits off the print's middle gray on the ridges' side
    /// (`blank_off_middle`): a wet smear as dark as the ridges. Such blocks and the blocks next
    /// to them as far off the middle, in areas of at least four periods squared, are left out of
    /// the print, so that the filter draws no ridges through them (noise alone gives about 1;
    /// docs/fingerprints.md, "Ridges through a solid wet area").
    /// 0 keeps every block and skips the measure. Default value: 2 (0 when a document written
    /// before the field existed is read back).
    #[serde(default = "default_blank_evidence")]
    pub blank_evidence: f64,
    /// How far off the print's middle gray (the median of its blocks' means) a block's mean must
    /// be for `blank_evidence` to call it blank, in units of the ridges' half swing (the median
    /// of the blocks' ridge amplitudes times √2), and at least by the block's own noise: faint
    /// ridges average to the middle gray, a smear sits at the ridges' level (about 1). Default
    /// value: 0.5.
    #[serde(default = "default_blank_off_middle")]
    pub blank_off_middle: f64,
    /// Standard deviation of the Gaussian smoothing the doubled-angle field, px. Default value: 16.
    pub orientation_sigma: f64,
    /// Length of the x-signature window across the ridges, px. Default value: 48.
    pub signature_length: u32,
    /// Shortest plausible ridge period, px (highest frequency 1/3 px⁻¹). Default value: 3.
    pub period_min: f64,
    /// Longest plausible ridge period, px (lowest frequency 1/25 px⁻¹). Default value: 25.
    pub period_max: f64,
    /// Period where none could be measured anywhere, px (500 dpi prints: about 9). Default value: 9.
    pub default_period: f64,
    /// Gabor envelope across the ridges, in periods (pyfing's GBFEN: 5/12). Default value: 0.4167.
    pub gabor_sigma_across: f64,
    /// Gabor envelope along the ridges, in periods. Default value: 0.4167.
    pub gabor_sigma_along: f64,
    /// Which enhancement: the Gabor filter or oriented smoothing. Default value: gabor.
    #[serde(default)]
    pub enhancement: Enhancement,
    /// Length of the oriented smoothing's average along the ridge, in periods (SourceAFIS: 14 px
    /// at 500 dpi, about 1.5 periods). Default value: 1.5.
    #[serde(default = "smoothing_along")]
    pub smoothing_along: f64,
    /// Minutiae closer than this to the print's border (or the image's) are dropped, px
    /// (pyfing's SBMEX: 10); the margin is the larger of this and `border_periods` ridge
    /// periods. Default value: 0 (the margin in periods alone; 12 before `border_periods`).
    pub border_margin: f64,
    /// Ridges with two free ends shorter than this are fragments or islands; both ends are
    /// dropped, in ridge periods. Default value: 1.5.
    pub fragment_periods: f64,
    /// A branch from a bifurcation to an ending shorter than this is a spur; both go, in ridge
    /// periods. Default value: 1.
    pub spur_periods: f64,
    /// A bar between two bifurcations shorter than this and across the flow is a bridge between
    /// neighbouring ridges; both go, in ridge periods. Default value: 1.5.
    pub bridge_periods: f64,
    /// Two endings facing each other along the flow closer than this are one broken ridge; both
    /// go, in ridge periods. Default value: 2.
    pub gap_periods: f64,
    /// Minutiae with at least two others closer than this are a cloud (noise, a scar, a core
    /// turning too fast); the cloud's minutiae of low quality go (`cloud_quality`), in ridge
    /// periods; 0 keeps clouds. Default value: 1.
    pub cloud_periods: f64,
    /// A traced ridge counts for the minutiae only when at least this share of its length lies
    /// on ridges the gray image confirms (darker than its local mean, for dark ridges): the
    /// filter's ghost ridges in valleys wider than the period have no ends or forks of the
    /// finger's; 0 counts every traced ridge. Default value: 0.5 (also when a document written
    /// before the field existed is read back).
    #[serde(default = "default_confirmed_share")]
    pub confirmed_share: f64,
    /// Minutiae closer than this to the print's border (or the image's) are dropped, in ridge
    /// periods (the print's median), when that is more than `border_margin`: the ridges are cut
    /// there, not ended: a margin in the print's own scale (docs/fingerprints.md, "Matching
    /// benchmark", "The border in ridge periods"). Default value: 1.25 (0 when a document
    /// written before the field existed is read back: its `border_margin` in px alone).
    #[serde(default = "default_border_periods")]
    pub border_periods: f64,
    /// The border margin, in ridge periods (the print's median), for a minutia that points into
    /// the print: a ridge the print's outline cuts ends pointing out of the print, while an
    /// ending or a fork that points inward is the finger's even near the outline. Such a
    /// minutia within the border margin is kept when it is at least this far from the border
    /// and its quality reaches `inward_border_quality` (near the image's edge, its ridges also
    /// confirmed: `inward_border_confirmed`). A matcher finds more of the finger's minutiae near
    /// the outline (docs/fingerprints.md, "Matching benchmark"). 0 gives every minutia the
    /// border margin. Default value: 0.75 (also when a document written before the field
    /// existed is read back).
    #[serde(default = "default_inward_border_periods")]
    pub inward_border_periods: f64,
    /// The share of the median quality of the print's minutiae that a minutia pointing into
    /// the print needs to be kept within the border margin (`inward_border_periods`): near the
    /// outline, noise beyond the finger is traced as short ridges in blocks of low contrast.
    /// Default value: 0.6 (also when a document written before the field existed is read
    /// back).
    #[serde(default = "default_inward_border_quality")]
    pub inward_border_quality: f64,
    /// A minutia kept within the border margin by `inward_border_periods` and near the image's
    /// edge (within the margin of it) needs at least this share of the first two ridge periods
    /// of each of its ridges on the ridges the gray image confirms: where the finger's outline
    /// nears the image's edge, the noise of the bare skin beyond it is traced as short ridges
    /// the gray image confirms only by chance. 0 asks nothing. Default value: 0.8 (also when a
    /// document written before the field existed is read back).
    #[serde(default = "default_inward_border_confirmed")]
    pub inward_border_confirmed: f64,
    /// A minutia of a cloud (`cloud_periods`) goes only when its quality is below this share of
    /// the median quality of the print's minutiae: a cluster of minutiae where the ridges are
    /// clear and coherent is the finger's (a core, a delta, short ridges), a cluster in noise
    /// is not. 0 keeps every cloud. Default value: 0.6 (also
    /// when a document written before the field existed is read back).
    #[serde(default = "default_cloud_quality")]
    pub cloud_quality: f64,
    /// Whether to measure the enhanced ridges' width for [`Decisions::stroke_width`] (their
    /// median chord, the JSON's `stroke_width`): chords along every line and column of the
    /// print's binary, about 2.5 % of a 500 ppi print's work, read by nothing but that field.
    /// false leaves it 0; the command-line tool asks for it only when it writes a JSON (or
    /// `--debug` pictures). Default value: true (also when a document written before the field
    /// existed is read back; a document lists the field only when it is false).
    ///
    /// [`Decisions::stroke_width`]: crate::Decisions::stroke_width
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub ridge_width: bool,
}

impl Default for FingerprintParams {
    fn default() -> Self {
        FingerprintParams {
            block: 8,
            gradient_sigma: 1.0,
            segment_threshold: 0.2,
            response_threshold: 0.2,
            blank_evidence: 2.0,
            blank_off_middle: default_blank_off_middle(),
            orientation_sigma: 16.0,
            signature_length: 48,
            period_min: 3.0,
            period_max: 25.0,
            default_period: 9.0,
            gabor_sigma_across: 5.0 / 12.0,
            gabor_sigma_along: 5.0 / 12.0,
            enhancement: Enhancement::Gabor,
            smoothing_along: smoothing_along(),
            border_margin: 0.0,
            fragment_periods: 1.5,
            spur_periods: 1.0,
            bridge_periods: 1.5,
            gap_periods: 2.0,
            cloud_periods: 1.0,
            confirmed_share: 0.5,
            border_periods: 1.25,
            inward_border_periods: default_inward_border_periods(),
            inward_border_quality: default_inward_border_quality(),
            inward_border_confirmed: default_inward_border_confirmed(),
            cloud_quality: default_cloud_quality(),
            ridge_width: true,
        }
    }
}

fn default_border_periods() -> f64 {
    0.0
}

fn default_inward_border_quality() -> f64 {
    0.6
}

fn default_inward_border_periods() -> f64 {
    0.75
}

fn default_inward_border_confirmed() -> f64 {
    0.8
}

fn default_blank_evidence() -> f64 {
    0.0
}

fn default_blank_off_middle() -> f64 {
    0.5
}

fn default_cloud_quality() -> f64 {
    0.6
}

fn smoothing_along() -> f64 {
    1.5
}

impl FingerprintParams {
    /// Checks every range the fields document.
    pub fn validate(&self) -> crate::error::Result<()> {
        let fail = |field: &'static str, reason: String| {
            Err(crate::error::Error::InvalidParam { field, reason })
        };
        if !(2..=64).contains(&self.block) {
            return fail(
                "fingerprint.block",
                format!("must be 2-64 px, got {}", self.block),
            );
        }
        if !(8..=256).contains(&self.signature_length) {
            return fail(
                "fingerprint.signature_length",
                format!("must be 8-256 px, got {}", self.signature_length),
            );
        }
        if !(self.response_threshold.is_finite() && (0.0..=1.0).contains(&self.response_threshold))
        {
            return fail(
                "fingerprint.response_threshold",
                format!("must be 0-1, got {}", self.response_threshold),
            );
        }
        let non_negative = [
            ("fingerprint.gradient_sigma", self.gradient_sigma),
            ("fingerprint.border_margin", self.border_margin),
            ("fingerprint.fragment_periods", self.fragment_periods),
            ("fingerprint.spur_periods", self.spur_periods),
            ("fingerprint.bridge_periods", self.bridge_periods),
            ("fingerprint.gap_periods", self.gap_periods),
            ("fingerprint.cloud_periods", self.cloud_periods),
            ("fingerprint.border_periods", self.border_periods),
            (
                "fingerprint.inward_border_periods",
                self.inward_border_periods,
            ),
            (
                "fingerprint.inward_border_quality",
                self.inward_border_quality,
            ),
            ("fingerprint.cloud_quality", self.cloud_quality),
            ("fingerprint.blank_evidence", self.blank_evidence),
            ("fingerprint.blank_off_middle", self.blank_off_middle),
        ];
        if !(self.inward_border_confirmed.is_finite()
            && (0.0..=1.0).contains(&self.inward_border_confirmed))
        {
            return fail(
                "fingerprint.inward_border_confirmed",
                format!("must be 0-1, got {}", self.inward_border_confirmed),
            );
        }
        if !(self.confirmed_share.is_finite() && (0.0..=1.0).contains(&self.confirmed_share)) {
            return fail(
                "fingerprint.confirmed_share",
                format!("must be 0-1, got {}", self.confirmed_share),
            );
        }
        for (field, v) in non_negative {
            if !(v.is_finite() && (0.0..=1000.0).contains(&v)) {
                return fail(field, format!("must be 0-1000, got {v}"));
            }
        }
        let positive = [
            (
                "fingerprint.segment_threshold",
                self.segment_threshold,
                10.0,
            ),
            (
                "fingerprint.orientation_sigma",
                self.orientation_sigma,
                1000.0,
            ),
            (
                "fingerprint.gabor_sigma_across",
                self.gabor_sigma_across,
                2.0,
            ),
            ("fingerprint.gabor_sigma_along", self.gabor_sigma_along, 2.0),
            ("fingerprint.smoothing_along", self.smoothing_along, 8.0),
        ];
        for (field, v, most) in positive {
            if !(v.is_finite() && v > 0.0 && v <= most) {
                return fail(field, format!("must be > 0 and <= {most}, got {v}"));
            }
        }
        if !(self.period_min >= 2.0
            && self.period_min < self.period_max
            && self.period_max <= 64.0
            && self.default_period >= self.period_min
            && self.default_period <= self.period_max)
        {
            return fail(
                "fingerprint.period_min",
                format!(
                    "need 2 <= period_min < period_max <= 64 with default_period between, got \
                     {}, {}, {}",
                    self.period_min, self.period_max, self.default_period
                ),
            );
        }
        Ok(())
    }
}

/// Parameters of the whole pipeline, grouped by the stage that reads them: the front end
/// ([`FrontEndParams`]: limits, binarization, the mask and the gray-level refinements), the
/// method's graph (§3.1-3.3, [`MethodParams`]), the fit (§3.4, [`FitParams`]), what the project
/// adds after the method ([`FinishParams`]: clean-up and the skeleton), the switched-off
/// experiments ([`ExperimentParams`]) and the fingerprint front end ([`FingerprintParams`]).
///
/// serde flattens the groups: the JSON object (the `parameters` of the output, docs/json.md) and
/// the Python keywords are one flat set of names, `threshold`, `k`, `smoothness`, ..., in this
/// order. Build it from [`Params::default`], [`Params::paper`] or [`Params::fingerprint`] and
/// assign the fields: more may be added.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Params {
    /// The front end: from the input to the point set.
    #[serde(flatten)]
    pub front_end: FrontEndParams,
    /// The method's graph (§3.1-3.3).
    #[serde(flatten)]
    pub method: MethodParams,
    /// The fit (§3.4).
    #[serde(flatten)]
    pub fit: FitParams,
    /// The clean-up and the skeleton.
    #[serde(flatten)]
    pub finish: FinishParams,
    /// The switched-off experiments.
    #[serde(flatten)]
    pub experiments: ExperimentParams,
    /// The fingerprint front end ([`Params::fingerprint`]): segmentation, orientation field, ridge
    /// period and Gabor enhancement in place of the text binarization, and the fingerprint
    /// minutiae filter (docs/fingerprints.md). Default value: `None` (off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fingerprint: Option<FingerprintParams>,
}

/// The front end's parameters ([`Params::front_end`]): what an input may make the library
/// allocate, how gray levels become ink (docs/design.md, "The front end"), the mask's clean-up
/// before the points are built, and the gray-level refinements of images. The limits sit here,
/// before the binarization, because the front end checks them while it decodes the input and
/// builds its points (and the JSON lists them in that place).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct FrontEndParams {
    /// Binarization method. Default value: [`FrontEndParams::DEFAULT_THRESHOLD`] (automatic).
    pub threshold: Threshold,
    /// Ink polarity. Default value: [`FrontEndParams::DEFAULT_POLARITY`] (automatic).
    pub polarity: Polarity,
    /// Size limits. Default value: [`Limits::default`].
    pub limits: Limits,
    /// Dropout mode (docs/design.md, adaptation 2): `None` decides from the image (background
    /// specks of 3 px or less exceeding `dropout_fraction` of the ink), `Some(b)` forces it.
    /// Default value: [`FrontEndParams::DEFAULT_DROPOUT`] (`None`).
    pub dropout: Option<bool>,
    /// Share of ink pixels that tiny background holes must exceed to switch dropout mode on.
    /// Default value: [`FrontEndParams::DEFAULT_DROPOUT_FRACTION`] (0.015).
    pub dropout_fraction: f64,
    /// Ink components (8-connected) of fewer pixels than this are dropped before tracing, for
    /// speckled scans (the `speckle` warning suggests a value). Default value:
    /// [`FrontEndParams::DEFAULT_MIN_AREA`] (0: none dropped).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub min_area: usize,
    /// Whether the centerline of a gray image is placed below the pixel from its gray levels:
    /// each polyline point moves along its normal (at most 0.75 px, never off the ink) to the
    /// middle of the stroke's cross-section in the gray (docs/design.md, "The front end"). Bilevel
    /// images, masks and point lists are not refined. Default value:
    /// [`FrontEndParams::DEFAULT_SUBPIXEL`] (`true`); paper `false`.
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub subpixel: bool,
    /// Whether thresholded ink pixels that the gray shows lighter than the ink on both sides of
    /// them (a crotch between two arms or a gap between two strokes that the blur filled) go back
    /// to the paper (docs/design.md, "The front end"). Bilevel images and masks are not touched;
    /// neither is a fixed threshold. Default value: [`FrontEndParams::DEFAULT_VALLEYS`] (`true`);
    /// paper `false`.
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub valleys: bool,
    /// Whether, with [`Polarity::Auto`], a thick field of ink holding light strokes (white
    /// letters on a dark banner) is read as a ground: its pixels go to the paper and the strokes
    /// it encloses become the ink (docs/design.md, "The front end"). Default value:
    /// [`FrontEndParams::DEFAULT_REVERSE_GROUNDS`] (`true`); paper `false`.
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub reverse_grounds: bool,
    /// The kinds of regions that are not strokes (halftone photos, frames, page edges; docs/design.md,
    /// "The front end") traced anyway: the front end finds them on images and leaves the others
    /// out of the trace. Default value: [`FrontEndParams::DEFAULT_KEEP_REGIONS`] (none: every
    /// region found is left out).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keep_regions: Vec<RegionKind>,
}

/// A kind of region that is not strokes ([`FrontEndParams::keep_regions`],
/// [`crate::Region`]), written in snake case (`halftone`, `frame`, `page_edge`, `faint`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum RegionKind {
    /// A halftone or photo inside the page: solid or dotted ink, no open paper, no strokes of the
    /// page's width.
    Halftone,
    /// A band of thick ink along the image's edge (a scanner's frame, a border), or a ring of
    /// lines around the page's content (a printed border, the edges of a bound book's pages).
    Frame,
    /// A dark field reaching the image's edge: what lies beyond a page's edge.
    PageEdge,
    /// Ink that never reaches half the contrast of the page's text, away from it: show-through
    /// from the back of the page, a paper's grain or a cover's cracks that a local threshold
    /// read as ink.
    Faint,
}

impl RegionKind {
    /// Every kind, in the order above.
    pub const ALL: [RegionKind; 4] = [
        RegionKind::Halftone,
        RegionKind::Frame,
        RegionKind::PageEdge,
        RegionKind::Faint,
    ];

    /// The name the JSON and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            RegionKind::Halftone => "halftone",
            RegionKind::Frame => "frame",
            RegionKind::PageEdge => "page_edge",
            RegionKind::Faint => "faint",
        }
    }
}

impl std::fmt::Display for RegionKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FrontEndParams {
    /// Default of [`FrontEndParams::threshold`]: Otsu or the local threshold, decided per image.
    pub const DEFAULT_THRESHOLD: Threshold = Threshold::Auto;
    /// Default of [`FrontEndParams::polarity`]: decided from stroke evidence.
    pub const DEFAULT_POLARITY: Polarity = Polarity::Auto;
    /// Default of [`FrontEndParams::dropout`]: decided from the image.
    pub const DEFAULT_DROPOUT: Option<bool> = None;
    /// Default of [`FrontEndParams::dropout_fraction`].
    pub const DEFAULT_DROPOUT_FRACTION: f64 = 0.015;
    /// Default of [`FrontEndParams::min_area`]: no component dropped.
    pub const DEFAULT_MIN_AREA: usize = 0;
    /// Default of [`FrontEndParams::subpixel`].
    pub const DEFAULT_SUBPIXEL: bool = true;
    /// Default of [`FrontEndParams::valleys`].
    pub const DEFAULT_VALLEYS: bool = true;
    /// Default of [`FrontEndParams::reverse_grounds`].
    pub const DEFAULT_REVERSE_GROUNDS: bool = true;
    /// Default of [`FrontEndParams::keep_regions`]: none kept.
    pub const DEFAULT_KEEP_REGIONS: Vec<RegionKind> = Vec::new();
}

impl Default for FrontEndParams {
    fn default() -> Self {
        FrontEndParams {
            threshold: Self::DEFAULT_THRESHOLD,
            polarity: Self::DEFAULT_POLARITY,
            limits: Limits::default(),
            dropout: Self::DEFAULT_DROPOUT,
            dropout_fraction: Self::DEFAULT_DROPOUT_FRACTION,
            min_area: Self::DEFAULT_MIN_AREA,
            subpixel: Self::DEFAULT_SUBPIXEL,
            valleys: Self::DEFAULT_VALLEYS,
            reverse_grounds: Self::DEFAULT_REVERSE_GROUNDS,
            keep_regions: Self::DEFAULT_KEEP_REGIONS,
        }
    }
}

/// The method's parameters ([`Params::method`]): the sampling disks of §3.1, the node graph and
/// its clusters of §3.2, the merging of §3.3.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct MethodParams {
    /// How `r_min` is chosen (§3.1). Default value: [`MethodParams::DEFAULT_R_MIN_RULE`]
    /// ([`RMinRule::StrokeWidth`]); paper [`RMinRule::Spacing`].
    pub r_min_rule: RMinRule,
    /// `r_min` factor: with [`RMinRule::StrokeWidth`] `r_min = max(3 Dis_ave, r_min_factor ·
    /// w_loc)` (β of docs/design.md, adaptation 3); with [`RMinRule::Spacing`] `r_min =
    /// r_min_factor · Dis_ave`. Default value: [`MethodParams::DEFAULT_R_MIN_FACTOR`] (1.0);
    /// paper 10.
    pub r_min_factor: f64,
    /// `r_max / r_min`. Default value: [`MethodParams::DEFAULT_R_MAX_FACTOR`] (3); paper 6.
    pub r_max_factor: f64,
    /// Radius growth factor per step of §3.1. Default value:
    /// [`MethodParams::DEFAULT_R_GROWTH`] (1.25).
    pub r_growth: f64,
    /// Linearity threshold of Eq. (3): a disk is linear when `l > linearity`. Default value:
    /// [`MethodParams::DEFAULT_LINEARITY`] (0.9).
    pub linearity: f64,
    /// Use the rim "arms" test as well as PCA to detect non-linear nodes (adaptation 5). Default
    /// value: [`MethodParams::DEFAULT_ARMS_TEST`] (`true`); paper `false`.
    pub arms_test: bool,
    /// `k` nearest neighbours for point-set input (§3.2). Default value:
    /// [`MethodParams::DEFAULT_K`] (5).
    pub k: usize,
    /// Which nodes form clusters (§3.2). Default value: [`MethodParams::DEFAULT_CLUSTER_RULE`]
    /// ([`ClusterRule::NonLinear`]); paper [`ClusterRule::EqualDistance`].
    pub cluster_rule: ClusterRule,
    /// Cluster link length, in units of `r_min` (§3.2: edges shorter than this join non-linear
    /// nodes into one cluster). Default value: [`MethodParams::DEFAULT_CLUSTER_LINK`] (1.5).
    pub cluster_link: f64,
    /// Merge groups: degree > 2 nodes of a cluster are merged only when all are within this many
    /// `r_min` of each other (adaptation 9). Default value:
    /// [`MethodParams::DEFAULT_MERGE_SPAN`] (2.0); the paper merges whole clusters (infinity).
    /// JSON has no infinity: serde_json writes it as `null`, which reads back as infinity
    /// (docs/json.md).
    #[serde(deserialize_with = "null_is_infinity")]
    pub merge_span: f64,
}

impl MethodParams {
    /// Default of [`MethodParams::r_min_rule`].
    pub const DEFAULT_R_MIN_RULE: RMinRule = RMinRule::StrokeWidth;
    /// Default of [`MethodParams::r_min_factor`]: one local stroke width.
    pub const DEFAULT_R_MIN_FACTOR: f64 = 1.0;
    /// Default of [`MethodParams::r_max_factor`].
    pub const DEFAULT_R_MAX_FACTOR: f64 = 3.0;
    /// Default of [`MethodParams::r_growth`].
    pub const DEFAULT_R_GROWTH: f64 = 1.25;
    /// Default of [`MethodParams::linearity`].
    pub const DEFAULT_LINEARITY: f64 = 0.9;
    /// Default of [`MethodParams::arms_test`].
    pub const DEFAULT_ARMS_TEST: bool = true;
    /// Default of [`MethodParams::k`].
    pub const DEFAULT_K: usize = 5;
    /// Default of [`MethodParams::cluster_rule`].
    pub const DEFAULT_CLUSTER_RULE: ClusterRule = ClusterRule::NonLinear;
    /// Default of [`MethodParams::cluster_link`].
    pub const DEFAULT_CLUSTER_LINK: f64 = 1.5;
    /// Default of [`MethodParams::merge_span`].
    pub const DEFAULT_MERGE_SPAN: f64 = 2.0;
}

impl Default for MethodParams {
    fn default() -> Self {
        MethodParams {
            r_min_rule: Self::DEFAULT_R_MIN_RULE,
            r_min_factor: Self::DEFAULT_R_MIN_FACTOR,
            r_max_factor: Self::DEFAULT_R_MAX_FACTOR,
            r_growth: Self::DEFAULT_R_GROWTH,
            linearity: Self::DEFAULT_LINEARITY,
            arms_test: Self::DEFAULT_ARMS_TEST,
            k: Self::DEFAULT_K,
            cluster_rule: Self::DEFAULT_CLUSTER_RULE,
            cluster_link: Self::DEFAULT_CLUSTER_LINK,
            merge_span: Self::DEFAULT_MERGE_SPAN,
        }
    }
}

/// The fit's parameters ([`Params::fit`]): the equalized nodes, their L1 medians and the least
/// squares of Eq. (4) (§3.4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct FitParams {
    /// The smoothness term of Eq. (4). Default value: [`FitParams::DEFAULT_LAPLACIAN`]
    /// ([`LaplacianRule::Held`]); paper [`LaplacianRule::Uniform`].
    pub laplacian: LaplacianRule,
    /// Laplacian weight `w` of Eq. (4). Default value: [`FitParams::DEFAULT_SMOOTHNESS`] (1.0).
    pub smoothness: f64,
    /// Data weight on junctions and endpoints in the fit (adaptation 12). Default value:
    /// [`FitParams::DEFAULT_ANCHOR_WEIGHT`] (10); paper 1.
    pub anchor_weight: f64,
    /// Weiszfeld iterations for the L1 medians of §3.4, at most [`MAX_WEISZFELD_ITERATIONS`].
    /// Default value: [`FitParams::DEFAULT_WEISZFELD_ITERATIONS`] (20).
    pub weiszfeld_iterations: usize,
    /// Node spacing after equalization, in units of the median stroke width, at least 3 px
    /// (adaptation 12). Default value: [`FitParams::DEFAULT_SPACING_FACTOR`] (1.0).
    pub spacing_factor: f64,
}

impl FitParams {
    /// Default of [`FitParams::laplacian`].
    pub const DEFAULT_LAPLACIAN: LaplacianRule = LaplacianRule::Held;
    /// Default of [`FitParams::smoothness`].
    pub const DEFAULT_SMOOTHNESS: f64 = 1.0;
    /// Default of [`FitParams::anchor_weight`].
    pub const DEFAULT_ANCHOR_WEIGHT: f64 = 10.0;
    /// Default of [`FitParams::weiszfeld_iterations`].
    pub const DEFAULT_WEISZFELD_ITERATIONS: usize = 20;
    /// Default of [`FitParams::spacing_factor`].
    pub const DEFAULT_SPACING_FACTOR: f64 = 1.0;
}

impl Default for FitParams {
    fn default() -> Self {
        FitParams {
            laplacian: Self::DEFAULT_LAPLACIAN,
            smoothness: Self::DEFAULT_SMOOTHNESS,
            anchor_weight: Self::DEFAULT_ANCHOR_WEIGHT,
            weiszfeld_iterations: Self::DEFAULT_WEISZFELD_ITERATIONS,
            spacing_factor: Self::DEFAULT_SPACING_FACTOR,
        }
    }
}

/// What the project adds after the method ([`Params::finish`]), both on by default and off in
/// the paper's preset: the clean-up of the graph and the skeleton that carries its geometry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct FinishParams {
    /// Clean-up after §3.3 (contract hole-free cycles, prune spurs, collapse short bars) and the
    /// placement of ends and junctions (adaptations 10, 11, 13, 14). Default value:
    /// [`FinishParams::DEFAULT_CLEANUP`] (`true`); paper `false`.
    pub cleanup: bool,
    /// Skeleton-carried geometry ([`crate::thin`], docs/quality.md "Fidelity directions"): a
    /// topology-preserving pixel skeleton carries the polylines and every hole, the method's
    /// graph decides crossings and spurs and lends its fitted lines where it follows the
    /// skeleton. Images only, not in dropout mode. Default value:
    /// [`FinishParams::DEFAULT_SKELETON`] (`true`); paper `false` (the node graph's own
    /// polylines, §3.4).
    pub skeleton: bool,
}

impl FinishParams {
    /// Default of [`FinishParams::cleanup`].
    pub const DEFAULT_CLEANUP: bool = true;
    /// Default of [`FinishParams::skeleton`].
    pub const DEFAULT_SKELETON: bool = true;
}

impl Default for FinishParams {
    fn default() -> Self {
        FinishParams {
            cleanup: Self::DEFAULT_CLEANUP,
            skeleton: Self::DEFAULT_SKELETON,
        }
    }
}

/// Experiments that measured no better than the defaults and stay switched off
/// ([`Params::experiments`]): each is off by default and in the paper's preset, has no
/// command-line flag, and is written in the JSON only when on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct ExperimentParams {
    /// Disks that respect the ink (§3.1 on pixel images): a sampling disk never holds ink hidden
    /// from its center (ink reached around a hole or across a gap from another stroke), so it
    /// never wraps around a cell or counter nor spans two strokes. The radius is cut below the
    /// first hidden point, down to at most `width / 2 + Dis_ave`. Needs a pixel grid; off in
    /// dropout mode (its ink has holes by nature). Default value: `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub ink_disks: bool,
    /// Clusters that never span two junction sites (§3.2): two non-linear nodes are linked only
    /// when the straight segment between them stays on the ink, so nodes on either side of a
    /// cell, a counter or a gap between strokes are never one region. Default value: `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub site_clusters: bool,
    /// Dense re-fit (§3.4): the fitted nodes are spaced [`DENSE_SPACING`] `Dis_ave` apart instead
    /// of `h`, so each node's Voronoi cell is a thin slice of its stroke and its L1 median lies
    /// on the stroke's middle. Default value: `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub dense_fit: bool,
    /// Junctions on the ink (§3.4, adaptation 14): a junction whose fitted position is off its
    /// component's ink moves to the nearest ink point of its own cell. Default value: `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub junctions_on_ink: bool,
    /// Spurs decided by the ink (skeleton stage, docs/design.md, "Skeleton-carried geometry"):
    /// a terminal branch at a junction is kept when the ink that only it explains (the junction's
    /// edges drawn with and without it, each with a round pen of its median measured width)
    /// outweighs the cost of one more part (half a square of the stroke's width), instead of
    /// when its ink reaches past the junction's disk by more than `max(1.5 px, 0.4 w)`
    /// (docs/quality.md, "Deciding spurs by the ink"). Default value: `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub decide_by_ink: bool,
    /// Cusps decided by the ink (skeleton stage, docs/design.md, "Skeleton-carried geometry"):
    /// a Y whose short stub (at most 3 stroke widths) points away from both legs (more than 120
    /// degrees from each) on strokes at least 2.5 px wide is a bend at the stub's tip when the
    /// two legs drawn straight on to that tip, with a round pen of each leg's median width,
    /// explain the ink no worse than the Y with its stub does, less the cost of one part
    /// (docs/quality.md, "Session of 2026-12-07, sixteenth: cusps decided by the ink"). Off: it
    /// cut real short arms (hanzi junction recall .876 -> .861) for few script spurs. Default
    /// value: `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cusps_by_ink: bool,
}

/// Node spacing of [`ExperimentParams::dense_fit`], in `Dis_ave` (px on images).
pub const DENSE_SPACING: f64 = 2.0;

impl Params {
    /// The paper's own rules and values, a preset whose every field can still be changed:
    /// `r_min = 10 Dis_ave`, `r_max = 6 r_min`, `k = 5`, `w = 1`, linearity 0.9, no arms test,
    /// clusters of nodes at equal distance, whole-cluster merging, a uniform Laplacian with
    /// uniform data weights, no clean-up, no skeleton, no gray-level refinements, the
    /// experiments off.
    pub fn paper() -> Self {
        Params {
            front_end: FrontEndParams {
                subpixel: false,
                valleys: false,
                reverse_grounds: false,
                ..FrontEndParams::default()
            },
            method: MethodParams {
                r_min_rule: RMinRule::Spacing,
                r_min_factor: 10.0,
                r_max_factor: 6.0,
                arms_test: false,
                cluster_rule: ClusterRule::EqualDistance,
                merge_span: f64::INFINITY,
                ..MethodParams::default()
            },
            fit: FitParams {
                laplacian: LaplacianRule::Uniform,
                anchor_weight: 1.0,
                ..FitParams::default()
            },
            finish: FinishParams {
                cleanup: false,
                skeleton: false,
            },
            experiments: ExperimentParams::default(),
            fingerprint: None,
        }
    }

    /// The fingerprint preset, a preset whose every field can still be changed: the default
    /// tracing with the fingerprint front end ([`FingerprintParams::default`]) in place of the text
    /// binarization.
    pub fn fingerprint() -> Self {
        Params {
            fingerprint: Some(FingerprintParams::default()),
            ..Params::default()
        }
    }

    /// Checks every range the fields document; the one place where parameters are validated.
    /// The error names the field (`threshold.window`, `limits.max_side`, ...), so the command
    /// line can name its flag.
    pub fn validate(&self) -> crate::error::Result<()> {
        if let Some(fingerprint) = &self.fingerprint {
            fingerprint.validate()?;
        }
        fn fail(field: &'static str, reason: String) -> crate::error::Result<()> {
            Err(crate::error::Error::InvalidParam { field, reason })
        }
        let positive = [
            ("r_min_factor", self.method.r_min_factor),
            ("spacing_factor", self.fit.spacing_factor),
            ("anchor_weight", self.fit.anchor_weight),
            ("cluster_link", self.method.cluster_link),
        ];
        for (field, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return fail(field, format!("must be > 0, got {value}"));
            }
        }
        // Infinity is the paper's whole-cluster merging.
        if self.method.merge_span.is_nan() || self.method.merge_span <= 0.0 {
            return fail(
                "merge_span",
                format!("must be > 0, got {}", self.method.merge_span),
            );
        }
        if !(self.method.r_max_factor.is_finite() && self.method.r_max_factor >= 1.0) {
            return fail(
                "r_max_factor",
                format!("must be >= 1, got {}", self.method.r_max_factor),
            );
        }
        if !(self.method.r_growth.is_finite() && self.method.r_growth > 1.0) {
            return fail(
                "r_growth",
                format!("must be > 1, got {}", self.method.r_growth),
            );
        }
        if !(self.method.linearity > 0.5 && self.method.linearity < 1.0) {
            return fail(
                "linearity",
                format!("must be in (0.5, 1), got {}", self.method.linearity),
            );
        }
        if !(self.fit.smoothness.is_finite() && self.fit.smoothness >= 0.0) {
            return fail(
                "smoothness",
                format!("must be >= 0, got {}", self.fit.smoothness),
            );
        }
        if !(2..=64).contains(&self.method.k) {
            return fail("k", format!("must be in 2-64, got {}", self.method.k));
        }
        if self.fit.weiszfeld_iterations > MAX_WEISZFELD_ITERATIONS {
            return fail(
                "weiszfeld_iterations",
                format!(
                    "must be at most {MAX_WEISZFELD_ITERATIONS}, got {}",
                    self.fit.weiszfeld_iterations
                ),
            );
        }
        if !(self.front_end.dropout_fraction > 0.0 && self.front_end.dropout_fraction < 1.0) {
            return fail(
                "dropout_fraction",
                format!("must be in (0, 1), got {}", self.front_end.dropout_fraction),
            );
        }
        if let Threshold::Sauvola { window, k } = self.front_end.threshold {
            if window < 3 || window % 2 == 0 {
                return fail(
                    "threshold.window",
                    format!("must be odd and >= 3, got {window}"),
                );
            }
            if !(0.0..=1.0).contains(&k) {
                return fail("threshold.k", format!("must be in [0, 1], got {k}"));
            }
        }
        let limits = [
            ("limits.max_pixels", self.front_end.limits.max_pixels),
            ("limits.max_side", u64::from(self.front_end.limits.max_side)),
            ("limits.max_points", self.front_end.limits.max_points),
            ("limits.max_pages", self.front_end.limits.max_pages),
        ];
        for (field, value) in limits {
            if value == 0 {
                return fail(field, "must be at least 1".into());
            }
        }
        Ok(())
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn yes() -> bool {
    true
}

fn is_yes(b: &bool) -> bool {
    *b
}

/// A number, or `null` for infinity: what serde_json writes for [`Params::merge_span`] of the
/// paper's preset (the one field whose valid range holds infinity).
fn null_is_infinity<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::INFINITY))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every preset reads back from the JSON it is written as, alone and as the `parameters` of
    /// a trace's document.
    #[test]
    fn every_preset_round_trips_through_its_json() {
        let mut paper_fingerprint = Params::paper();
        paper_fingerprint.fingerprint = Some(FingerprintParams::default());
        let mut sauvola = Params::default();
        sauvola.front_end.threshold = Threshold::Sauvola {
            window: Threshold::DEFAULT_SAUVOLA_WINDOW,
            k: Threshold::DEFAULT_SAUVOLA_K,
        };
        sauvola.front_end.min_area = 12;
        sauvola.front_end.dropout = Some(true);
        for (name, params) in [
            ("default", Params::default()),
            ("paper", Params::paper()),
            ("fingerprint", Params::fingerprint()),
            ("paper with fingerprint", paper_fingerprint),
            ("sauvola", sauvola),
        ] {
            let text = serde_json::to_string(&params).expect("serialize");
            let back: Params = serde_json::from_str(&text)
                .unwrap_or_else(|err| panic!("{name}: {err} reading {text}"));
            assert_eq!(back, params, "{name}");
            let meta = crate::export::json::JsonMeta::new(params.clone());
            let document =
                crate::export::json::to_string(&crate::stroke_graph::StrokeGraph::default(), &meta);
            let value: serde_json::Value = serde_json::from_str(&document).expect("document");
            let back = Params::deserialize(&value["parameters"])
                .unwrap_or_else(|err| panic!("{name}: {err} reading the document's parameters"));
            assert_eq!(back, params, "{name}: {}", value["parameters"]);
        }
        assert!(serde_json::to_string(&Params::paper())
            .expect("serialize")
            .contains("\"merge_span\":null"));
    }

    #[test]
    fn fingerprint_parameters_without_the_confirmed_share_read_with_its_default() {
        let mut value = serde_json::to_value(Params::fingerprint()).expect("serialize");
        let fields = value["fingerprint"].as_object_mut().expect("an object");
        assert!(fields.remove("confirmed_share").is_some());
        let params = Params::deserialize(&value).expect("reads");
        assert_eq!(params, Params::fingerprint());
    }

    #[test]
    fn merge_span_reads_numbers_and_null_only() {
        let mut value = serde_json::to_value(Params::default()).expect("serialize");
        value["merge_span"] = serde_json::json!(3.5);
        let params = Params::deserialize(&value).expect("a number");
        assert_eq!(params.method.merge_span, 3.5);
        value["merge_span"] = serde_json::Value::Null;
        assert_eq!(
            Params::deserialize(&value).expect("null").method.merge_span,
            f64::INFINITY
        );
        value["merge_span"] = serde_json::json!("wide");
        assert!(Params::deserialize(&value).is_err());
    }
}
