//! The library's one error type. Messages are written for the person running the tool: each says
//! what went wrong and, where there is one, what to try instead.

use std::path::PathBuf;

/// Everything that can go wrong while reading input or tracing it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The input file could not be read (missing, unreadable, a directory…).
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file that failed.
        path: PathBuf,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// The bytes are not an image format ridgeline can decode, or the image is damaged.
    #[error("cannot decode image: {0}")]
    Decode(String),
    /// The image or point set is larger than the configured limits allow.
    #[error("{}", Error::limit_sentence(.what, .actual, .limit, .field))]
    Limit {
        /// What was measured ("image pixels", "points", …).
        what: &'static str,
        /// The measured size.
        actual: u64,
        /// The configured limit.
        limit: u64,
        /// The parameter that raises the limit, named as in the JSON (`limits.max_pixels`, a
        /// field of [`crate::Limits`]); the command line names its flag, Python its keyword.
        field: &'static str,
    },
    /// A point-set file has a line that is not two finite numbers.
    #[error("point list line {line}: {message}")]
    PointParse {
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    /// A point file (PLY, CSV with a header, XYZ) is malformed in a way no line number names:
    /// its header, its binary body, its columns.
    #[error("point file: {0}")]
    PointFile(String),
    /// The parameters contradict each other or are out of range.
    #[error("invalid parameter: {0}")]
    InvalidParams(String),
    /// A picture could not be encoded (the stage pictures of [`crate::debug::stage_pngs`]).
    #[error("cannot encode picture {0}")]
    Encode(String),
    /// The minutiae do not fit the record format asked for (ISO/IEC 19794-2: at most 255
    /// minutiae, 14-bit coordinates, 16-bit image sides).
    #[error("cannot write the minutiae record: {0}")]
    Record(String),
    /// One field of [`Params`](crate::Params) is outside its documented range.
    #[error("invalid parameter {field}: {reason}")]
    InvalidParam {
        /// The field, as a path from `Params` (`threshold.window`, `limits.max_side`, ...).
        field: &'static str,
        /// What is wrong with its value ("must be odd and >= 3, got 4").
        reason: String,
    },
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The sentence of an [`Error::Limit`], with `raise` saying how the limit is raised: the
    /// library names the field (`limits.max_pixels`), the command line its flag and Python its
    /// keyword, each in this one sentence.
    pub fn limit_sentence(
        what: &str,
        actual: impl std::fmt::Display,
        limit: impl std::fmt::Display,
        raise: &str,
    ) -> String {
        format!(
            "{what}: {actual}, over the limit of {limit}; raise {raise} if the input is trusted"
        )
    }
}
