//! What the front end decided for an image, and the warnings a trace raises when its result is
//! probably wrong (docs/design.md, "The front end"). Both go into the JSON and onto stderr, so a
//! user can see why a trace looks the way it does and which flag overrides it.

use crate::params::{Enhancement, RegionKind};
use serde::Serialize;

/// The side of the threshold traced as ink ([`Decisions::polarity`]), written `"dark"` or
/// `"light"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum InkSide {
    /// Dark strokes on light paper.
    Dark,
    /// Light strokes on a dark ground.
    Light,
}

impl InkSide {
    /// [`InkSide::Dark`] when the ink is dark, else [`InkSide::Light`].
    pub fn of(dark_ink: bool) -> InkSide {
        if dark_ink {
            InkSide::Dark
        } else {
            InkSide::Light
        }
    }

    /// The name the JSON writes: `dark` or `light`.
    pub fn name(self) -> &'static str {
        match self {
            InkSide::Dark => "dark",
            InkSide::Light => "light",
        }
    }
}

impl std::fmt::Display for InkSide {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The front end's decisions for one image.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Decisions {
    /// The side traced as ink.
    pub polarity: InkSide,
    /// How sure the polarity is, in [0, 1) (0: a coin toss); `None` when `--polarity` forced it.
    pub polarity_confidence: Option<f64>,
    /// The threshold used.
    pub threshold: ThresholdUsed,
    /// The stroke width the image shows (the most common chord of the ink, px; with
    /// `--fingerprint`, the enhanced ridges' median chord); 0 for an empty image, and for a
    /// print traced with [`FingerprintParams::ridge_width`] false.
    ///
    /// [`FingerprintParams::ridge_width`]: crate::FingerprintParams::ridge_width
    pub stroke_width: f64,
    /// Pixels on which Otsu's global level and the local threshold disagree, as a share of the
    /// ink (uneven light, varying contrast); above [`UNEVEN_LIGHT`] the automatic threshold is
    /// the local one. 0 when not measured.
    pub uneven_light: f64,
    /// Whether dropout mode (5x5 neighbourhoods for broken, speckled ink) was on; `None` until
    /// the points are built, and for a point list.
    pub dropout: Option<bool>,
    /// The share of the ink traced in dropout mode (decided per group of nearby components);
    /// `None` when `dropout` is.
    pub dropout_share: Option<f64>,
    /// The grounds reversed (polarity per region: thick fields of ink holding light strokes,
    /// such as white letters on a dark banner, whose strokes were traced as the ink instead),
    /// by bounding box; empty (and not written) when there was none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reversed_grounds: Vec<Ground>,
    /// The regions that are not strokes (halftone photos, frames, page edges), by kind and
    /// bounding box: left out of the trace unless their kind is in
    /// [`FrontEndParams::keep_regions`](crate::FrontEndParams::keep_regions); empty (and not
    /// written) when there was none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<Region>,
    /// What the fingerprint front end measured on the print; `None` (and not written) without
    /// `--fingerprint`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub print: Option<PrintDecisions>,
}

/// What the fingerprint front end measured on a print (docs/fingerprints.md).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PrintDecisions {
    /// The median ridge period of the blocks inside the print, px (0 for an empty print).
    pub ridge_period: f64,
    /// The share of the image's blocks inside the print's segmentation mask.
    pub print_share: f64,
    /// The median coherence of the ridge flow over the blocks inside the print, in [0, 1]:
    /// low on a smudged or noisy print.
    pub coherence: f64,
}

/// The threshold actually applied, with its settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "method", rename_all = "lowercase")]
pub enum ThresholdUsed {
    /// No threshold: the image has one gray level, so no ink.
    Uniform,
    /// Otsu's global level: gray levels at or below it are dark.
    Otsu {
        /// The level.
        level: u8,
    },
    /// A fixed level given by the user.
    Fixed {
        /// The level.
        level: u8,
    },
    /// The local threshold: halfway between the darkest and lightest levels of blocks of
    /// `window` px, interpolated between block centers.
    Local {
        /// Block side, px (about six stroke widths).
        window: u32,
    },
    /// The fingerprint front end: ridges are where the enhanced image (`enhancement`: `gabor` or
    /// `smoothing`) is positive and the segmentation mask holds the print.
    Enhanced {
        /// The contextual enhancement applied.
        enhancement: Enhancement,
    },
    /// Sauvola's threshold, as the user asked.
    Sauvola {
        /// Window side, px.
        window: u32,
        /// Sensitivity.
        k: f64,
    },
}

/// Disagreement between the global and the local split, as a share of the ink, above which the
/// automatic threshold goes local.
pub const UNEVEN_LIGHT: f64 = 0.1;

/// Something about a trace that is probably wrong, with what to try.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Warning {
    /// A stable name: `polarity_uncertain`, `one_huge_component`, `mesh`, `speckle`,
    /// `high_degree`.
    pub code: &'static str,
    /// One sentence for people, ending with the flag to try.
    pub message: String,
}

/// A reversed ground's bounding box, px.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Ground {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

/// A region of an image that is not strokes, px ([`Decisions::regions`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Region {
    /// What it is.
    pub kind: RegionKind,
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}
