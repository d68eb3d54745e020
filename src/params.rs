//! Every tunable of the pipeline in one place, with the paper's symbol and unit.
//!
//! The defaults are the values that measure best on pixel images (see `DESIGN.md` and the quality
//! benchmark); [`Params::paper`] gives the paper's own values so the two can be compared.

use serde::{Deserialize, Serialize};

/// How gray levels become ink and paper.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", tag = "method")]
pub enum Threshold {
    /// Otsu's global threshold. The default.
    Otsu,
    /// A fixed gray level 0-255; pixels darker than or equal to it are ink (for dark ink).
    Fixed {
        /// The level.
        level: u8,
    },
    /// Sauvola's adaptive threshold for unevenly lit scans.
    Sauvola {
        /// Side of the square window in pixels (odd). Default 31.
        window: u32,
        /// Sensitivity `k`. Default 0.2.
        k: f64,
    },
}

/// Which side of the threshold is ink. Written `auto`, `dark` and `light`, as the command line
/// spells them (`darkink` and `lightink` are still read).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Polarity {
    /// Decide from the image: the minority side (after thresholding) is ink. The default.
    Auto,
    /// Dark strokes on light paper.
    #[serde(rename = "dark", alias = "darkink")]
    DarkInk,
    /// Light strokes (ridges) on a dark background.
    #[serde(rename = "light", alias = "lightink")]
    LightInk,
}

/// Bounds on what one input may make the library allocate.
///
/// Decoding is refused from the image header beyond `max_pixels` or `max_side`. Tracing needs at
/// most about 450 bytes per foreground point plus 6 bytes per image pixel (peak RSS measured on
/// 12-megapixel pages, see `docs/bad-input.md`), and `max_points` is checked before any per-point
/// array is allocated, so the three limits bound the memory of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Largest image, in pixels (width x height), that will be decoded. Default 100 megapixels.
    pub max_pixels: u64,
    /// Largest image side in pixels. Default 65 535.
    pub max_side: u32,
    /// Largest number of foreground points traced. Default 50 million.
    pub max_points: u64,
    /// Largest number of pages (image file directories) of a multi-page TIFF; a file with more is
    /// refused before any page is decoded. Pages are decoded one at a time, each within the other
    /// limits. Default 1000.
    #[serde(default = "default_max_pages")]
    pub max_pages: u64,
}

fn default_max_pages() -> u64 {
    Limits::default().max_pages
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_pixels: 100_000_000,
            max_side: 65_535,
            max_points: 50_000_000,
            max_pages: 1000,
        }
    }
}

/// Largest [`Params::weiszfeld_iterations`]: more would only cost time (the medians converge in
/// far fewer).
pub const MAX_WEISZFELD_ITERATIONS: usize = 1000;

/// Parameters of the whole pipeline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// Binarization method. Default [`Threshold::Otsu`].
    pub threshold: Threshold,
    /// Ink polarity. Default [`Polarity::Auto`].
    pub polarity: Polarity,
    /// Size limits. Default [`Limits::default`].
    pub limits: Limits,
    /// Dropout mode (§ design 1, 11): `None` decides from the image (background specks of 3 px or
    /// less exceeding `dropout_fraction` of the ink), `Some(b)` forces it.
    pub dropout: Option<bool>,
    /// Share of ink pixels that tiny background holes must exceed to switch dropout mode on.
    /// Default 0.015.
    pub dropout_fraction: f64,
    /// Paper mode: `r_min = r_min_factor · Dis_ave` instead of one stroke width. Default false.
    pub paper: bool,
    /// `r_min` factor: in the default mode `r_min = max(3 Dis_ave, r_min_factor · w_loc)` (β of the
    /// design, default 1.0); in paper mode `r_min = r_min_factor · Dis_ave` (default 10).
    pub r_min_factor: f64,
    /// `r_max / r_min`. Default 3 (paper: 6).
    pub r_max_factor: f64,
    /// Radius growth factor per step of §3.1. Default 1.25.
    pub r_growth: f64,
    /// Linearity threshold of Eq. (3): a disk is linear when `l > linearity`. Default 0.9.
    pub linearity: f64,
    /// Use the rim "arms" test as well as PCA to detect non-linear nodes (design 4). Default true.
    pub arms_test: bool,
    /// `k` nearest neighbours for point-set input (§3.2). Default 5.
    pub k: usize,
    /// Cluster link length, in units of `r_min` (§3.2: edges shorter than this join non-linear
    /// nodes into one cluster). Default 1.5.
    pub cluster_link: f64,
    /// Merge groups: degree > 2 nodes of a cluster are merged only when all are within this many
    /// `r_min` of each other (design 13). Default 2.0; the paper merges whole clusters (infinity).
    pub merge_span: f64,
    /// Laplacian weight `w` of Eq. (4). Default 1.0.
    pub smoothness: f64,
    /// Data weight on junctions and endpoints in the fit (design 9). Default 10 (paper: 1).
    pub anchor_weight: f64,
    /// Weiszfeld iterations for the L1 medians of §3.4, at most [`MAX_WEISZFELD_ITERATIONS`].
    /// Default 20.
    pub weiszfeld_iterations: usize,
    /// Node spacing after equalization, in units of the median stroke width, at least 3 px
    /// (design 9). Default 1.0.
    pub spacing_factor: f64,
    /// Clean-up after §3.3 (contract hole-free cycles, prune spurs, collapse short bars) and the
    /// placement of ends and junctions (design 8, 10, 14, 15). Default true; paper mode false.
    pub cleanup: bool,
    /// Skeleton-carried geometry (an experiment, [`crate::skeleton`]): the polylines follow a
    /// topology-preserving pixel skeleton, and the method's graph decides crossings and spurs.
    /// Images only, not in dropout mode. Default false; paper mode false.
    pub skeleton: bool,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            threshold: Threshold::Otsu,
            polarity: Polarity::Auto,
            limits: Limits::default(),
            dropout: None,
            dropout_fraction: 0.015,
            paper: false,
            r_min_factor: 1.0,
            r_max_factor: 3.0,
            r_growth: 1.25,
            linearity: 0.9,
            arms_test: true,
            k: 5,
            cluster_link: 1.5,
            merge_span: 2.0,
            smoothness: 1.0,
            anchor_weight: 10.0,
            weiszfeld_iterations: 20,
            spacing_factor: 1.0,
            cleanup: true,
            skeleton: false,
        }
    }
}

impl Params {
    /// The paper's own values: `r_min = 10 Dis_ave`, `r_max = 6 r_min`, `k = 5`, `w = 1`,
    /// linearity 0.9, no arms test, whole-cluster merging, uniform data weights, no clean-up.
    pub fn paper() -> Self {
        Params {
            paper: true,
            r_min_factor: 10.0,
            r_max_factor: 6.0,
            arms_test: false,
            merge_span: f64::INFINITY,
            anchor_weight: 1.0,
            cleanup: false,
            ..Params::default()
        }
    }

    /// Checks every range the fields document; the one place where parameters are validated.
    /// The error names the field (`threshold.window`, `limits.max_side`, ...), so the command
    /// line can name its flag.
    pub fn validate(&self) -> crate::Result<()> {
        fn fail(field: &'static str, reason: String) -> crate::Result<()> {
            Err(crate::Error::InvalidParam { field, reason })
        }
        let positive = [
            ("r_min_factor", self.r_min_factor),
            ("spacing_factor", self.spacing_factor),
            ("anchor_weight", self.anchor_weight),
            ("cluster_link", self.cluster_link),
        ];
        for (field, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return fail(field, format!("must be > 0, got {value}"));
            }
        }
        // Infinity is the paper's whole-cluster merging.
        if self.merge_span.is_nan() || self.merge_span <= 0.0 {
            return fail(
                "merge_span",
                format!("must be > 0, got {}", self.merge_span),
            );
        }
        if !(self.r_max_factor.is_finite() && self.r_max_factor >= 1.0) {
            return fail(
                "r_max_factor",
                format!("must be >= 1, got {}", self.r_max_factor),
            );
        }
        if !(self.r_growth.is_finite() && self.r_growth > 1.0) {
            return fail("r_growth", format!("must be > 1, got {}", self.r_growth));
        }
        if !(self.linearity > 0.5 && self.linearity < 1.0) {
            return fail(
                "linearity",
                format!("must be in (0.5, 1), got {}", self.linearity),
            );
        }
        if !(self.smoothness.is_finite() && self.smoothness >= 0.0) {
            return fail(
                "smoothness",
                format!("must be >= 0, got {}", self.smoothness),
            );
        }
        if !(2..=64).contains(&self.k) {
            return fail("k", format!("must be in 2-64, got {}", self.k));
        }
        if self.weiszfeld_iterations > MAX_WEISZFELD_ITERATIONS {
            return fail(
                "weiszfeld_iterations",
                format!(
                    "must be at most {MAX_WEISZFELD_ITERATIONS}, got {}",
                    self.weiszfeld_iterations
                ),
            );
        }
        if !(self.dropout_fraction > 0.0 && self.dropout_fraction < 1.0) {
            return fail(
                "dropout_fraction",
                format!("must be in (0, 1), got {}", self.dropout_fraction),
            );
        }
        if let Threshold::Sauvola { window, k } = self.threshold {
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
            ("limits.max_pixels", self.limits.max_pixels),
            ("limits.max_side", u64::from(self.limits.max_side)),
            ("limits.max_points", self.limits.max_points),
            ("limits.max_pages", self.limits.max_pages),
        ];
        for (field, value) in limits {
            if value == 0 {
                return fail(field, "must be at least 1".into());
            }
        }
        Ok(())
    }
}
