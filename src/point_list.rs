//! Point-list input, the paper's own setting: read `x y` or `x y z` lines, CSV with a header,
//! PLY and XYZ files ([`read`]), and build the plane's point set with symmetric k-nearest-neighbour
//! graphs from a k-d tree (§3.2: `k = 5`), `Dis_ave`, and a half-width from a distance transform
//! on a raster of the points (a set in space goes to [`crate::trace_points3d`]).

mod ply;

use std::collections::{HashMap, HashSet};

use foldhash::fast::FixedState;

use kiddo::ImmutableKdTree;
use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use crate::csr::symmetric_from_lists;
use crate::error::{Error, Result};
use crate::mask::{close3, ink_row_starts, squared_distance_rows, tiny_hole_pixels};
use crate::median::upper_median_by;
use crate::params::{Params, RMinRule};
use crate::point_index::{
    check_extent, cross_pairs, dear_max, dear_min, joined_parts, k_nearest, power_of_two_near,
    sparse_points, z_order, Cells,
};
use crate::point_set::{on_lattice, PointSet};
use crate::stroke_graph::StrokeGraph;

/// Largest dense raster for the half-width, in cells, on top of a share per point. Beyond it
/// (points spread thinly over a huge extent) a sparse search gives the same values.
const DENSE_CELLS_BASE: u64 = 1 << 22;
/// Largest raster side in cells (a whole number in f64 and far from i64 overflow).
const MAX_RASTER_SIDE: f64 = 1e15;
/// Dense raster cells allowed per point.
const DENSE_CELLS_PER_POINT: u64 = 32;

/// The points of a file: in the plane or in space.
#[derive(Clone, Debug, PartialEq)]
pub enum PointData {
    /// `x y` points.
    Plane(Vec<[f64; 2]>),
    /// `x y z` points.
    Space(Vec<[f64; 3]>),
}

impl PointData {
    /// Number of points.
    pub fn len(&self) -> usize {
        match self {
            PointData::Plane(list) => list.len(),
            PointData::Space(list) => list.len(),
        }
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Reads a point file, whose kind is told by its content, the file's `extension` (without the
/// dot) only breaking ties:
///
/// - PLY (starts with `ply`): the `vertex` element's `x y z`, ASCII or binary.
/// - Text with a header line naming its columns (CSV and the like): the columns named `x`, `y`
///   and, when there is one, `z` (any case, any order, other columns ignored).
/// - Text of `x y` lines (see [`parse`]) or `x y z` lines, decided by the first point's line;
///   in a `.xyz` file, the first three numbers of each line (normals or colours after them are
///   ignored).
///
/// Every malformed file is an error naming its line or what is wrong ([`Error::PointParse`],
/// [`Error::PointFile`]), never a panic.
pub fn read(bytes: &[u8], extension: Option<&str>) -> Result<PointData> {
    let extension = extension.map(str::to_ascii_lowercase);
    if ply::is_ply(bytes) || extension.as_deref() == Some("ply") {
        return ply::read(bytes).map(PointData::Space);
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|e| Error::PointFile(format!("not text (UTF-8) at byte {}", e.valid_up_to())))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let fields_of = |content: &str| -> Vec<String> {
        content
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .map(|f| f.trim_matches(|c| c == '"' || c == '\'').to_string())
            .collect()
    };
    let first = text
        .lines()
        .enumerate()
        .map(|(i, raw)| (i, raw.split('#').next().unwrap_or("").trim()))
        .find(|(_, content)| !content.is_empty());
    let Some((first_line, content)) = first else {
        return Ok(PointData::Plane(Vec::new()));
    };
    let fields = fields_of(content);
    let is_header = fields.iter().all(|f| f.parse::<f64>().is_err());
    if is_header {
        let names: Vec<String> = fields.iter().map(|f| f.to_ascii_lowercase()).collect();
        let find = |name: &str| names.iter().position(|n| n == name);
        return match (find("x"), find("y"), find("z")) {
            (Some(0), Some(1), None) if names.len() == 2 => parse(text).map(PointData::Plane),
            (Some(x), Some(y), None) => rows(text, first_line, [x, y], None).map(PointData::Plane),
            (Some(x), Some(y), Some(z)) => {
                rows(text, first_line, [x, y, z], None).map(PointData::Space)
            }
            // A header that names no coordinates: the columns by position.
            _ => by_count(text, Some(first_line), extension.as_deref()),
        };
    }
    by_count(text, None, extension.as_deref())
}

/// `x y` or `x y z` lines, decided by the first point's line (`header`: the 0-based line of a
/// header to skip).
fn by_count(text: &str, header: Option<usize>, extension: Option<&str>) -> Result<PointData> {
    let xyz = extension == Some("xyz");
    let first = text
        .lines()
        .enumerate()
        .filter(|(i, _)| Some(*i) != header)
        .map(|(i, raw)| (i, raw.split('#').next().unwrap_or("").trim()))
        .find(|(_, content)| !content.is_empty());
    let Some((line, content)) = first else {
        return Ok(PointData::Plane(Vec::new()));
    };
    let count = content
        .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
        .filter(|f| !f.is_empty())
        .count();
    match count {
        2 if !xyz => parse(text).map(PointData::Plane),
        3 => rows(text, header.unwrap_or(usize::MAX), [0, 1, 2], Some(3)).map(PointData::Space),
        n if xyz && n > 3 => {
            rows(text, header.unwrap_or(usize::MAX), [0, 1, 2], None).map(PointData::Space)
        }
        n => Err(Error::PointParse {
            line: line + 1,
            message: if xyz {
                format!("expected 3 numbers (x y z), found {n} values")
            } else {
                format!("expected 2 or 3 numbers (x y or x y z), found {n} values")
            },
        }),
    }
}

/// The numbers in `columns` of every line but blank ones, `#` comments and the 0-based line
/// `header`; with `exact`, each line must hold exactly that many values, else at least enough
/// for the columns.
fn rows<const D: usize>(
    text: &str,
    header: usize,
    columns: [usize; D],
    exact: Option<usize>,
) -> Result<Vec<[f64; D]>> {
    let needed = columns.iter().max().map_or(0, |m| m + 1);
    let axes = ["x", "y", "z"];
    let mut list = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() || i == header {
            continue;
        }
        let fields: Vec<&str> = content
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let wrong = match exact {
            Some(n) => fields.len() != n,
            None => fields.len() < needed,
        };
        if wrong {
            let want = match exact {
                Some(n) => format!("expected {n} numbers (x y z)"),
                None => format!("expected at least {needed} values"),
            };
            return Err(Error::PointParse {
                line,
                message: format!("{want}, found {} values", fields.len()),
            });
        }
        let mut point = [0.0; D];
        for (k, &c) in columns.iter().enumerate() {
            let field = fields[c].trim_matches(|c| c == '"' || c == '\'');
            let value = field.parse::<f64>().map_err(|_| Error::PointParse {
                line,
                message: format!("{} '{field}' is not a number", axes[k]),
            })?;
            if !value.is_finite() {
                return Err(Error::PointParse {
                    line,
                    message: format!("coordinate '{field}' is not finite"),
                });
            }
            point[k] = value;
        }
        list.push(point);
    }
    Ok(list)
}

/// Parses a point list: one point per line, two numbers separated by spaces, tabs, `,` or `;`.
/// Blank lines and `#` comments are skipped, and so is one header line (no number in it) before
/// the first point. Any other line that is not exactly two finite numbers is an
/// [`Error::PointParse`] naming its line.
pub fn parse(text: &str) -> Result<Vec<[f64; 2]>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut list = Vec::new();
    let mut header_allowed = true;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let fields: Vec<&str> = content
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if header_allowed && numbers.iter().all(Option::is_none) {
            header_allowed = false;
            continue;
        }
        header_allowed = false;
        if fields.len() != 2 {
            return Err(Error::PointParse {
                line,
                message: format!("expected 2 numbers (x y), found {} values", fields.len()),
            });
        }
        let mut point = [0.0; 2];
        for (k, (field, number)) in fields.iter().zip(&numbers).enumerate() {
            let value = number.ok_or_else(|| Error::PointParse {
                line,
                message: format!("'{field}' is not a number"),
            })?;
            if !value.is_finite() {
                return Err(Error::PointParse {
                    line,
                    message: format!("coordinate '{field}' is not finite"),
                });
            }
            point[k] = value;
        }
        list.push(point);
    }
    Ok(list)
}

/// Builds the point set for a list of points: exact duplicates removed (the first occurrence kept,
/// input order otherwise), symmetric `k`-nearest-neighbour lists, `Dis_ave`, and half-widths.
/// Output coordinates are the input's (half-widths beyond `f32` range, for lists spanning more
/// than about 1e38 units, read as infinite); [`crate::trace_points`] runs the
/// pipeline on the list moved and scaled to pixel-like units instead.
pub fn point_set(list: &[[f64; 2]], params: &Params) -> Result<PointSet> {
    let Prepared { mut set, units, .. } = point_set_in_units(list, params)?;
    units.restore_points(&mut set);
    Ok(set)
}

/// A list's coordinates in pixel-like units, and back (docs/design.md, "Hostile input").
///
/// The stages work in pixel-like units: `sample` quantizes squared distances in quarter units and
/// sizes its queue by them, the fit spaces nodes at least 3 units apart, widths are `f32`. A list
/// in other units (metres, 1e87, subnormals: the fuzzer's finds) asked for 51 GB or gave infinite
/// widths. The pipeline therefore runs on the list translated to its bounding box's corner and
/// divided by the power of two nearest `Dis_ave` (exact in binary floating point), and the
/// graph is mapped back. Pixel centers listed as points have `Dis_ave = 1`: only the translation
/// applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Units {
    /// The bounding box's lower corner, in list units (subtracted first).
    pub origin: [f64; 2],
    /// List units per pipeline unit: a power of two.
    pub scale: f64,
}

impl Units {
    fn to_list(self, p: [f64; 2]) -> [f64; 2] {
        [
            p[0] * self.scale + self.origin[0],
            p[1] * self.scale + self.origin[1],
        ]
    }

    /// Maps a point set in pipeline units back to list units.
    pub fn restore_points(&self, set: &mut PointSet) {
        for p in &mut set.points {
            *p = self.to_list(*p);
        }
        for h in &mut set.half_width {
            *h = (f64::from(*h) * self.scale) as f32;
        }
        set.spacing *= self.scale;
    }

    /// Maps a stroke graph in pipeline units back to list units. Edge ends are set to their
    /// vertices' positions exactly, so the graph stays valid whatever the scale.
    pub fn restore_graph(&self, graph: &mut StrokeGraph) {
        for v in &mut graph.vertices {
            v.pos = self.to_list(v.pos);
            v.width *= self.scale;
        }
        for e in &mut graph.edges {
            for p in &mut e.points {
                *p = self.to_list(*p);
            }
            for w in &mut e.widths {
                *w *= self.scale;
            }
            if let (Some(from), Some(to)) = (graph.vertices.get(e.from), graph.vertices.get(e.to)) {
                if let Some(first) = e.points.first_mut() {
                    *first = from.pos;
                }
                if let Some(last) = e.points.last_mut() {
                    *last = to.pos;
                }
            }
        }
    }
}

/// A point list made ready for the stages: [`point_set_in_units`]' answer.
pub(crate) struct Prepared {
    /// The point set, in pipeline units.
    pub set: PointSet,
    /// The pipeline's units.
    pub units: Units,
    /// `Some(share)` when the set is scattered and not strip-shaped (see [`NOT_STRIP_SHARE`]):
    /// `share` of its points lie in a linear window at some scale.
    pub not_strip: Option<f64>,
    /// How many distinct points were left out as a sparse cloud around the strips (see
    /// [`sparse_outliers`]).
    pub left_out: usize,
    /// The components of the set's neighbour graph, when they were found on the way (a
    /// scattered set): a label per point, shared by the points of a component.
    pub parts: Option<Vec<u32>>,
}

/// Like [`point_set`], in the pipeline's pixel-like [`Units`], which are returned with it, after
/// leaving out the points of a sparse cloud that is no strip at its own scale (see
/// [`sparse_outliers`]).
pub(crate) fn point_set_in_units(list: &[[f64; 2]], params: &Params) -> Result<Prepared> {
    let outliers = match prepare(list, params, true)? {
        Preparation::Ready(ready) => return Ok(*ready),
        Preparation::LeaveOut(outliers) => outliers,
    };
    // The kept points in their list order, traced as if they were the whole list.
    let points = without_duplicates(list);
    let kept: Vec<[f64; 2]> = points
        .iter()
        .zip(outliers)
        .filter(|(_, out)| !*out)
        .map(|(p, _)| *p)
        .collect();
    let left_out = points.len() - kept.len();
    // One look for a cloud: what stays is traced as it is.
    let Preparation::Ready(mut ready) = prepare(&kept, params, false)? else {
        return Err(Error::InvalidParams(
            "points left out twice (an internal error)".to_string(),
        ));
    };
    ready.left_out = left_out;
    Ok(*ready)
}

/// [`point_set_in_units`] on one list: the prepared set, or which of its distinct points (in
/// the order of `without_duplicates`) form a sparse cloud to leave out.
enum Preparation {
    Ready(Box<Prepared>),
    LeaveOut(Vec<bool>),
}

/// With `leave_out`, a sparse cloud found ([`sparse_outliers`]) is answered instead of the set.
fn prepare(list: &[[f64; 2]], params: &Params, leave_out: bool) -> Result<Preparation> {
    if list.len() as u64 > params.front_end.limits.max_points {
        return Err(Error::Limit {
            what: "points",
            actual: list.len() as u64,
            limit: params.front_end.limits.max_points,
            field: "limits.max_points",
        });
    }
    if let Some(i) = list
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(Error::PointParse {
            line: i + 1,
            message: format!(
                "point {} ({}, {}) is not finite",
                i + 1,
                list[i][0],
                list[i][1]
            ),
        });
    }
    let points = without_duplicates(list);
    let n = points.len();
    if n == 0 {
        let set = PointSet {
            offsets: vec![0],
            spacing: 1.0,
            ..PointSet::default()
        };
        let units = Units {
            origin: [0.0; 2],
            scale: 1.0,
        };
        return Ok(Preparation::Ready(Box::new(Prepared {
            set,
            units,
            not_strip: None,
            left_out: 0,
            parts: None,
        })));
    }

    // Work in coordinates translated to the origin: the tree and the raster then see numbers of
    // the size of the extent, not of the offset.
    let min = points
        .iter()
        .fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
    let local: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [p[0] - min[0], p[1] - min[1]])
        .collect();
    let extent = local.iter().fold(0.0f64, |m, p| m.max(p[0]).max(p[1]));
    check_extent(extent)?;

    // Powers of two only, so every rescaling below is exact (short of underflow). First the
    // extent to about 1, so that squared distances neither overflow nor underflow in the search.
    let coarse = power_of_two_near(extent);
    let mut local: Vec<[f64; 2]> = local
        .iter()
        .map(|p| [p[0] / coarse, p[1] / coarse])
        .collect();
    let k = params.method.k.min(n - 1);
    let Neighbours {
        offsets,
        neighbors,
        spacing,
        reach,
        parts,
    } = if k == 0 {
        Neighbours {
            offsets: vec![0; n + 1],
            neighbors: Vec::new(),
            spacing: 1.0,
            reach: Vec::new(),
            parts: None,
        }
    } else {
        nearest_neighbours(&local, k)?
    };
    let scattered = k > 0 && !on_lattice(&local, spacing);
    if scattered && leave_out {
        if let Some(outliers) = sparse_outliers(&local, &reach, k)? {
            return Ok(Preparation::LeaveOut(outliers));
        }
    }
    // Then `Dis_ave` to about 1 (see `Units`).
    let fine = if k == 0 {
        1.0
    } else {
        power_of_two_near(spacing)
    };
    for p in &mut local {
        *p = [p[0] / fine, p[1] / fine];
    }
    let spacing = if k == 0 { 1.0 } else { spacing / fine };
    // Points on the lattice of their own spacing (pixel centers listed as points) keep the image
    // path's distance transform; scattered points (the paper's unorganized strips) have mostly
    // empty cells inside the strip, so with the width-driven `r_min` (docs/design.md, adaptation
    // 3) their widths come from the local PCA of §3.1. The paper's own rule sizes its disks from
    // `Dis_ave` alone and keeps the raster's widths (its node spacing in the fit follows them).
    let mut half_width = half_widths(&local, spacing, params);
    let mut not_strip = None;
    if let (true, Some(part)) = (scattered, &parts) {
        let apply = params.method.r_min_rule == RMinRule::StrokeWidth;
        let (linear, windowed) = strip_half_widths(
            &local,
            spacing,
            (&offsets, &neighbors),
            part,
            &mut half_width,
            apply,
        );
        if windowed > 0 && (linear as f64) < NOT_STRIP_SHARE * windowed as f64 {
            not_strip = Some(linear as f64 / windowed as f64);
        }
    }
    let units = Units {
        origin: min,
        scale: coarse * fine,
    };
    let set = PointSet {
        points: local,
        half_width,
        offsets,
        neighbors,
        spacing,
        dropout: false,
        grid: None,
    };
    Ok(Preparation::Ready(Box::new(Prepared {
        set,
        units,
        not_strip,
        left_out: 0,
        parts,
    })))
}

/// A point is sparse when its `k`-th nearest neighbour is more than this many times farther than
/// the median point's: the set is a hundredfold sparser around it than at the median point. A
/// strip whose density falls tenfold along it, its ends and its edges stay far below (their
/// `k`-th neighbours are at most a few times farther).
const SPARSE_REACH: f64 = 10.0;

/// The points of a sparse cloud around the strips, to leave out (the paper's input is
/// strip-shaped, §3; uniform outliers around a strip are not): the points far sparser than the
/// set's own sampling ([`SPARSE_REACH`]), when there are any and, taken alone at their own
/// spacing, they are not strip-shaped either (the test of [`NOT_STRIP_SHARE`]; too few of them
/// to fill a window is no strip). A part sampled more sparsely than the rest but shaped as a
/// strip stays. `reach` holds each point's `k`-th neighbour distance.
fn sparse_outliers(points: &[[f64; 2]], reach: &[f64], k: usize) -> Result<Option<Vec<bool>>> {
    let Some((sparse, cloud)) = sparse_points(points, reach, SPARSE_REACH) else {
        return Ok(None);
    };
    let k = k.min(cloud.len() - 1);
    if k > 0 {
        let found = nearest_neighbours(&cloud, k)?;
        let part = match found.parts {
            Some(part) => part,
            None => crate::csr::parts(&found.offsets, &found.neighbors),
        };
        let mut widths = vec![0.0; cloud.len()];
        let (linear, windowed) = strip_half_widths(
            &cloud,
            found.spacing,
            (&found.offsets, &found.neighbors),
            &part,
            &mut widths,
            false,
        );
        if windowed > 0 && linear as f64 >= NOT_STRIP_SHARE * windowed as f64 {
            return Ok(None);
        }
    }
    Ok(Some(sparse))
}

/// A scattered set is strip-shaped when at least this share of its points (of those whose
/// window ever held [`STRIP_MIN_POINTS`] points) lie in a window that is linear by Eq. (3) at
/// some scale: the paper's input (§3, "a strip-shaped point set"). A uniform cloud is isotropic
/// at every scale and has none; strips have all but their junctions and ends.
const NOT_STRIP_SHARE: f64 = 0.5;

/// Drops exact repeats, keeping the first occurrence; `-0.0` equals `0.0`. The set only answers
/// "seen before?", so its iteration order never reaches the output.
fn without_duplicates(list: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut seen = HashSet::with_capacity_and_hasher(list.len(), FixedState::default());
    list.iter()
        .map(|p| [p[0] + 0.0, p[1] + 0.0])
        .filter(|p| seen.insert((p[0].to_bits(), p[1].to_bits())))
        .collect()
}

/// The symmetric `k`-nearest-neighbour graph of [`nearest_neighbours`].
struct Neighbours {
    /// CSR offsets into `neighbors`.
    offsets: Vec<u32>,
    /// The symmetric lists (§3.2), islands joined.
    neighbors: Vec<u32>,
    /// `Dis_ave`.
    spacing: f64,
    /// Each point's `k`-th neighbour distance.
    reach: Vec<f64>,
    /// For a scattered set (not on the lattice of its spacing), the graph's components, a label
    /// per point (see [`joined_parts`]).
    parts: Option<Vec<u32>>,
}

/// Symmetric k nearest neighbours (§3.2) as CSR, `Dis_ave` (mean nearest-neighbour distance),
/// each point's `k`-th neighbour distance and, for a scattered set, the graph's components.
/// Needs `1 <= k < points.len()` and distinct points.
fn nearest_neighbours(points: &[[f64; 2]], k: usize) -> Result<Neighbours> {
    let n = points.len();
    // The immutable tree: the mutable one fails on collinear or repeated coordinates (kiddo 6:
    // unsplittable buckets on pixel-like grids).
    let tree: ImmutableKdTree<f64, 2> = ImmutableKdTree::new_from_slice(points)
        .map_err(|e| Error::InvalidParams(format!("cannot index the points: {e:?}")))?;
    let order = z_order(points);
    let (lists, nearest) = k_nearest(points, &tree, &order, k);
    let spacing = nearest.iter().map(|d| d.0).sum::<f64>() / n as f64;
    let (bridges, parts) = if on_lattice(points, spacing) {
        (Vec::new(), None)
    } else {
        let (bridges, labels) = island_bridges(points, &tree, &order, &lists, k);
        let parts = joined_parts(labels, &bridges);
        (bridges, Some(parts))
    };
    drop(tree);
    // The symmetric relation: both directions of every k-nearest pair, mutual pairs once.
    let (offsets, neighbors) = symmetric_from_lists(n, &lists, k, &bridges);
    Ok(Neighbours {
        offsets,
        neighbors,
        spacing,
        reach: nearest.iter().map(|d| d.1).collect(),
        parts,
    })
}

/// How far, in its own `k`-th neighbour distances, a point of a scattered set reaches for a
/// point of another component of the `k`-nearest-neighbour graph (see [`island_bridges`]).
const ISLAND_REACH: f64 = 2.0;

/// Pairs that join the islands of a scattered set to the strip around them. Random points leave
/// clumps of a few points whose `k` nearest are each other and no outside point's nearest: the
/// `k`-nearest-neighbour graph (§3.2) cuts them off the strip they lie in, and each becomes a
/// part of its own (a dot in the middle of a stroke). A point is joined to every point of
/// another component within [`ISLAND_REACH`] times its `k`-th neighbour distance, the scale of
/// its own sampling, so parts a few spacings apart join and parts one strip width apart (many
/// spacings) stay apart. Lattice sets (pixel centers listed as points) keep their graph.
fn island_bridges(
    points: &[[f64; 2]],
    tree: &ImmutableKdTree<f64, 2>,
    order: &[u32],
    lists: &[u32],
    k: usize,
) -> (Vec<(u32, u32)>, Vec<u32>) {
    let n = points.len();
    let mut sets = UnionFind::<u32>::new(n);
    for (i, list) in lists.chunks(k).enumerate() {
        for &j in list.iter().filter(|&&j| j != u32::MAX) {
            sets.union(i as u32, j);
        }
    }
    let labels = sets.into_labeling();
    if labels.iter().all(|&l| l == labels[0]) {
        return (Vec::new(), labels);
    }
    // The distance to the farthest of the `k`: `hypot` only near the largest squared distance.
    let farthest = |i: usize| -> f64 {
        let p = points[i];
        let listed = lists[i * k..(i + 1) * k]
            .iter()
            .filter(|&&j| j != u32::MAX)
            .map(|&j| points[j as usize]);
        dear_max(
            listed,
            |q| (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]),
            |q| (p[0] - q[0]).hypot(p[1] - q[1]),
        )
        .unwrap_or(0.0)
    };
    let bridges = cross_pairs(points, tree, order, &labels, |i| ISLAND_REACH * farthest(i));
    (bridges, labels)
}

/// Half-widths for points without a pixel grid: rasterize the points onto cells of side `Dis_ave`
/// and run the image path's distance transform there. A strip sampled at spacing `Dis_ave` fills
/// about one cell per point, so the distance in cells from a point's cell to the nearest empty cell
/// counts point spacings to the strip's edge, and scaling by `Dis_ave` puts it back in the
/// coordinates' unit. For pixel centers listed as points this is exactly the image path.
fn half_widths(points: &[[f64; 2]], spacing: f64, params: &Params) -> Vec<f32> {
    let cell_of = |p: &[f64; 2]| -> (i64, i64) {
        // Cells centered on the lattice through the origin, so points on a lattice of step
        // `Dis_ave` land in consecutive cells despite rounding noise.
        (
            (p[0] / spacing + 0.5).floor() as i64,
            (p[1] / spacing + 0.5).floor() as i64,
        )
    };
    let cells: Vec<(i64, i64)> = points.iter().map(cell_of).collect();
    let width = cells.iter().map(|c| c.0).max().unwrap_or(0) as u64 + 1;
    let height = cells.iter().map(|c| c.1).max().unwrap_or(0) as u64 + 1;
    let area = width.saturating_mul(height);
    let cap = DENSE_CELLS_BASE
        .saturating_add(DENSE_CELLS_PER_POINT.saturating_mul(points.len() as u64))
        .min(params.front_end.limits.max_pixels);
    let scale = spacing as f32;
    if extent_cells(points, spacing) > MAX_RASTER_SIDE {
        // Cells this fine cannot be indexed; every point gets the strip's minimum half-width.
        return vec![scale; points.len()];
    }
    if area <= cap {
        let (w, h) = (width as usize, height as usize);
        let mut ink = vec![false; w * h];
        for &(x, y) in &cells {
            ink[y as usize * w + x as usize] = true;
        }
        // Dropout mode's rule: gaps between unevenly spread samples are closed as in images.
        let occupied = ink.iter().filter(|&&b| b).count();
        let close = params.front_end.dropout.unwrap_or_else(|| {
            tiny_hole_pixels(&ink, w, h) as f64
                > params.front_end.dropout_fraction * occupied as f64
        });
        if close {
            ink = close3(&ink, w, h);
        }
        let starts = ink_row_starts(&ink, w, h);
        let mut distance = vec![0f32; starts[h]];
        squared_distance_rows(&ink, w, h, &starts, &mut distance, |d2| {
            (d2 as f64).sqrt() as f32
        });
        // Rank of each ink cell in raster order = its slot in `distance`.
        let mut rank = vec![u32::MAX; w * h];
        let mut next = 0u32;
        for (slot, &on) in rank.iter_mut().zip(&ink) {
            if on {
                *slot = next;
                next += 1;
            }
        }
        cells
            .iter()
            .map(|&(x, y)| distance[rank[y as usize * w + x as usize] as usize] * scale)
            .collect()
    } else {
        sparse_half_widths(&cells, scale)
    }
}

/// Fewest points in a window for its covariance to say anything about the strip.
const STRIP_MIN_POINTS: f64 = 12.0;

/// The linearity `l` of Eq. (3) a window must exceed to measure a strip's width: §3.1's own
/// threshold for a linear disk.
const STRIP_LINEARITY: f64 = 0.9;

/// The linearity `l` of Eq. (3) a window must exceed to measure a strip's width: that of a band
/// across the smallest window allowed to measure it (a side twice the band's width, see
/// [`strip_half_widths`]), `l = (2w)^2 / ((2w)^2 + w^2)`. With §3.1's 0.9 a window had to be
/// three widths long, and the next window of the doubling scales (up to six widths) took in a
/// strip that runs beside or crosses at a small angle, measuring the two as one.
const WIDTH_LINEARITY: f64 = 0.8;

/// The share of a band's points (at the density of its own sampling) a window must hold to
/// measure its width: a window that is linear but hollow (the two sides of a loop, a figure 8's
/// lobe, two strips apart) is not one band. A uniform band fills its window's band fully (1),
/// a ring's lobe about a fifth.
const BAND_FILL: f64 = 0.4;

/// Half-widths of a strip of scattered points from the local PCA of §3.1 (Eq. (2)): across a band
/// of width `w` filled uniformly, the variance is `w^2 / 12`, so the half-width is
/// `sqrt(3 lambda_min)`. The covariance is taken over windows of 3 x 3 square cells of side `c`
/// around each point's cell, from per-cell moments of the point's own part (component of the
/// neighbour graph), at `c = 2 Dis_ave, 4 Dis_ave, ...`; a point takes the first window that is
/// linear by Eq. (3) and at least twice as wide as the width it measures there (below that the
/// window is filled and isotropic, and measures its own size). Points no window measures (in a
/// junction, a crossing) take the width of the nearest point that has one. Linear in the number
/// of points per scale, and the scales stop at the points' extent. Points of a part no window
/// measures keep `half_width`'s value, and so does every point unless the set is a strip at least
/// [`WIDE_STRIP_RATIO`] times wider than the raster says.
fn strip_half_widths(
    points: &[[f64; 2]],
    spacing: f64,
    (offsets, neighbors): (&[u32], &[u32]),
    part: &[u32],
    half_width: &mut [f32],
    apply: bool,
) -> (usize, usize) {
    let n = points.len();
    let extent = points.iter().fold(0.0f64, |m, p| m.max(p[0]).max(p[1]));
    let mut decided = vec![false; n];
    let mut windowed = vec![false; n];
    let mut linear = vec![false; n];
    let mut measured = vec![f32::NAN; n];
    // Windows hold only points of the point's own part: a strip one width from another (parallel
    // strips) must not read the two as one wide strip.
    let mut cell = 2.0 * spacing;
    let mut cells: Option<Cells<2>> = None;
    let mut moments: Vec<[f64; 7]> = Vec::new();
    // Each point's nearest neighbour distance: the window's own sampling (see [`BAND_FILL`]).
    // (`hypot` only near the smallest squared distance.)
    let nearest: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|p| {
            let a = points[p];
            let listed = neighbors[offsets[p] as usize..offsets[p + 1] as usize]
                .iter()
                .map(|&q| points[q as usize]);
            dear_min(
                listed,
                |b| (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]),
                |b| (a[0] - b[0]).hypot(a[1] - b[1]),
            )
            .unwrap_or(f64::INFINITY)
        })
        .collect();
    while decided.iter().zip(&linear).any(|(&d, &l)| !d || !l) && cell <= 2.0 * extent.max(spacing)
    {
        let grid = match cells.take() {
            None => Cells::new(points, part, cell),
            Some(finer) => finer.coarser(points, part, 0.5 * cell),
        };
        // Moments per cell: count, sum x, sum y, sum xx, sum xy, sum yy (relative to the cell's
        // corner, so the sums stay small), summed in point order.
        moments.clear();
        moments.resize(grid.keys.len(), [0.0; 7]);
        for ((p, &slot), &d) in points.iter().zip(&grid.point_slot).zip(&nearest) {
            let c = grid.keys[slot as usize].1;
            let (x, y) = (p[0] - c[0] as f64 * cell, p[1] - c[1] as f64 * cell);
            let m = &mut moments[slot as usize];
            m[0] += 1.0;
            m[1] += x;
            m[2] += y;
            m[3] += x * x;
            m[4] += x * y;
            m[5] += y * y;
            if d.is_finite() {
                m[6] += d;
            }
        }
        // Per cell: `None` when its window holds too few points, else the half-width it measures
        // when it is a piece of strip (NaN when not, see [`WIDTH_LINEARITY`]) and whether it is
        // linear by §3.1's own threshold (the strip-shape test counts those). Every point of a cell has the same window,
        // so each occupied cell is measured once.
        let measure = |_: &(u32, [i64; 2]), slots: &[u32]| -> Option<(f32, bool)> {
            // The window's moments about the cell's corner.
            let mut w = [0.0f64; 7];
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    let slot = slots[(3 * (dy + 1) + dx + 1) as usize];
                    if slot != u32::MAX {
                        let m = &moments[slot as usize];
                        let (ox, oy) = (dx as f64 * cell, dy as f64 * cell);
                        w[0] += m[0];
                        w[1] += m[1] + ox * m[0];
                        w[2] += m[2] + oy * m[0];
                        w[3] += m[3] + 2.0 * ox * m[1] + ox * ox * m[0];
                        w[4] += m[4] + ox * m[2] + oy * m[1] + ox * oy * m[0];
                        w[5] += m[5] + 2.0 * oy * m[2] + oy * oy * m[0];
                        w[6] += m[6];
                    }
                }
            }
            if w[0] < STRIP_MIN_POINTS {
                return None;
            }
            let (mx, my) = (w[1] / w[0], w[2] / w[0]);
            let sxx = (w[3] / w[0] - mx * mx).max(0.0);
            let sxy = w[4] / w[0] - mx * my;
            let syy = (w[5] / w[0] - my * my).max(0.0);
            // Eigenvalues of the 2 x 2 covariance (Eq. (2)).
            let half_trace = 0.5 * (sxx + syy);
            let root = (0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy).sqrt();
            let lambda_min = (half_trace - root).max(0.0);
            let lambda_max = half_trace + root;
            let half = (3.0 * lambda_min).sqrt();
            // The window must be a piece of strip: linear by Eq. (3) as §3.1's disks must be. A
            // crossing, a T or a Y is not linear at any scale (its arms spread both ways), and
            // its smallest eigenvalue grows with the window: it takes its arms' width below.
            let linear = lambda_max > STRIP_LINEARITY * (lambda_min + lambda_max);
            let wide = 3.0 * cell >= 4.0 * half;
            // A band of half-width `half` and length `sqrt(12 lambda_max)` filled at the
            // density its mean nearest-neighbour distance `d` says (`1 / (4 d^2)` for random
            // points) holds `12 sqrt(lambda_min lambda_max) / (4 d^2)` points.
            let spread = w[6] / w[0];
            let band = 3.0 * (lambda_min * lambda_max).sqrt();
            let filled = w[0] * spread * spread >= BAND_FILL * band;
            let measures = lambda_max > WIDTH_LINEARITY * (lambda_min + lambda_max) && filled;
            Some((
                if measures && wide {
                    half as f32
                } else {
                    f32::NAN
                },
                linear && wide,
            ))
        };
        let per_cell: Vec<Option<(f32, bool)>> = grid.windows(measure);
        for i in 0..n {
            if let Some((half, strip)) = per_cell[grid.point_slot[i] as usize] {
                windowed[i] = true;
                linear[i] |= strip;
                if !decided[i] && half.is_finite() {
                    decided[i] = true;
                    measured[i] = half;
                }
            }
        }
        cells = Some(grid);
        cell *= 2.0;
    }
    let counts = (
        linear.iter().filter(|&&l| l).count(),
        windowed.iter().filter(|&&w| w).count(),
    );
    if !apply {
        return counts;
    }
    // One decision per set: the PCA widths replace the raster's only where the set is a strip
    // much wider than its spacing (the raster's cells inside it are mostly empty, so its
    // distances count one or two cells); a thin curve sampled at its spacing keeps the raster's.
    let mut ratios: Vec<f32> = measured
        .iter()
        .zip(half_width.iter())
        .filter(|(m, _)| m.is_finite())
        .map(|(m, h)| m / h.max(f32::MIN_POSITIVE))
        .collect();
    if ratios.len() * 2 < n {
        return counts;
    }
    let median = upper_median_by(&mut ratios, f32::total_cmp).unwrap_or(0.0);
    if median < WIDE_STRIP_RATIO {
        return counts;
    }
    spread_to_undecided(offsets, neighbors, &mut measured);
    for (h, m) in half_width.iter_mut().zip(&measured) {
        if m.is_finite() {
            *h = h.max(*m);
        }
    }
    counts
}

/// Gives every point without a width of its own (in a junction, a crossing, a sharp bend: no
/// window around it is linear) the width of the nearest point that has one, nearest by hops over
/// the neighbour graph: the width of the arms that meet there. Breadth first from every measured
/// point at once, in index order, so the result does not depend on anything but the set.
fn spread_to_undecided(offsets: &[u32], neighbors: &[u32], measured: &mut [f32]) {
    let mut queue: std::collections::VecDeque<u32> = (0..measured.len() as u32)
        .filter(|&i| measured[i as usize].is_finite())
        .collect();
    while let Some(p) = queue.pop_front() {
        let value = measured[p as usize];
        let (from, to) = (
            offsets[p as usize] as usize,
            offsets[p as usize + 1] as usize,
        );
        for &q in &neighbors[from..to] {
            if !measured[q as usize].is_finite() {
                measured[q as usize] = value;
                queue.push_back(q);
            }
        }
    }
}

/// How many times wider than the raster's half-widths the PCA's must be, at the median point, for
/// a set to be read as a wide strip of scattered points.
const WIDE_STRIP_RATIO: f32 = 2.0;

/// The larger side of the points' bounding box (from the origin), in cells of side `spacing`.
fn extent_cells(points: &[[f64; 2]], spacing: f64) -> f64 {
    points.iter().fold(0.0f64, |m, p| m.max(p[0]).max(p[1])) / spacing
}

/// The same distances as the dense raster (without closing), by searching square rings around
/// each cell in a set of the occupied cells (cells are nonnegative; outside is empty). The set
/// holds 8 x 8 tiles of cells as bit masks in a hash table, so most of a ring's probes read the
/// center's own tile: on a long strip of 10^6 points the sorted list searched before cost a cache
/// miss at each of its 20 levels, for each of a ring's 12 probes.
fn sparse_half_widths(cells: &[(i64, i64)], scale: f32) -> Vec<f32> {
    let occupied = CellSet::new(cells);
    cells
        .par_iter()
        .map(|&(x, y)| {
            // The last tile read: most probes fall in it.
            let mut last: Option<((i64, i64), u64)> = None;
            let mut empty = |x: i64, y: i64| {
                if x < 0 || y < 0 {
                    return true;
                }
                let tile = (x >> TILE_SHIFT, y >> TILE_SHIFT);
                let mask = match last {
                    Some((t, mask)) if t == tile => mask,
                    _ => {
                        let mask = occupied.mask(tile);
                        last = Some((tile, mask));
                        mask
                    }
                };
                mask & tile_bit(x, y) == 0
            };
            let mut best = i64::MAX;
            let mut r = 1i64;
            while r * r < best {
                for d in -r..=r {
                    for (dx, dy) in [(d, -r), (d, r), (-r, d), (r, d)] {
                        if empty(x + dx, y + dy) {
                            best = best.min(dx * dx + dy * dy);
                        }
                    }
                }
                r += 1;
            }
            (best as f64).sqrt() as f32 * scale
        })
        .collect()
}

/// Tiles of `2^TILE_SHIFT` cells a side: 64 cells, one bit each in a `u64`.
const TILE_SHIFT: u32 = 3;

/// The bit of a nonnegative cell in its tile's mask.
fn tile_bit(x: i64, y: i64) -> u64 {
    let side = 1i64 << TILE_SHIFT;
    1u64 << (((y & (side - 1)) << TILE_SHIFT) | (x & (side - 1)))
}

/// The occupied cells of a set of nonnegative cells, as the mask ([`tile_bit`]) of each tile
/// that holds any, keyed by the tile. It only answers "which cells of this tile are occupied?",
/// so no order of it reaches the output.
struct CellSet(HashMap<(i64, i64), u64, foldhash::fast::FixedState>);

impl CellSet {
    fn new(cells: &[(i64, i64)]) -> Self {
        let mut tiles = HashMap::with_hasher(foldhash::fast::FixedState::default());
        for &(x, y) in cells {
            *tiles.entry((x >> TILE_SHIFT, y >> TILE_SHIFT)).or_insert(0) |= tile_bit(x, y);
        }
        CellSet(tiles)
    }

    /// The occupied cells of `tile` as bits ([`tile_bit`]); 0 for a tile with none.
    fn mask(&self, tile: (i64, i64)) -> u64 {
        self.0.get(&tile).copied().unwrap_or(0)
    }
}

/// Image-like extent (width, height) covering all points.
pub(crate) fn extent(list: &[[f64; 2]]) -> (u32, u32) {
    let mut w = 0.0f64;
    let mut h = 0.0f64;
    for p in list {
        w = w.max(p[0]);
        h = h.max(p[1]);
    }
    (
        (w.ceil() as u32).saturating_add(1),
        (h.ceil() as u32).saturating_add(1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_error(text: &str) -> (usize, String) {
        match parse(text) {
            Err(Error::PointParse { line, message }) => (line, message),
            other => panic!("expected a parse error for {text:?}, got {other:?}"),
        }
    }

    #[test]
    fn parses_separators_comments_and_header() {
        let text = "x,y\n# a comment\n1 2\n\n3,4\n5;6\n7\t8 # trailing\n -1.5e1 , 2.25 \r\n";
        assert_eq!(
            parse(text).unwrap(),
            vec![
                [1.0, 2.0],
                [3.0, 4.0],
                [5.0, 6.0],
                [7.0, 8.0],
                [-15.0, 2.25]
            ]
        );
        assert!(parse("").unwrap().is_empty());
        assert!(parse("# only comments\n\n").unwrap().is_empty());
    }

    #[test]
    fn parse_errors_name_the_line() {
        assert_eq!(parse_error("1 2\n3 4 5\n").0, 2);
        assert_eq!(parse_error("1 2\n3\n").0, 2);
        let (line, message) = parse_error("x y\n1 2\n\n# c\n3 abc\n");
        assert_eq!(line, 5);
        assert!(message.contains("abc"), "{message}");
        assert_eq!(parse_error("1 2\nNaN 3\n").0, 2);
        assert_eq!(parse_error("inf 3\n").0, 1);
        // Only one header, and only before the first point.
        assert_eq!(parse_error("x y\nu v\n1 2\n").0, 2);
        assert_eq!(parse_error("1 2\nx y\n").0, 2);
    }

    fn is_symmetric(set: &PointSet) -> bool {
        (0..set.len() as u32).all(|i| {
            set.neighbors_of(i)
                .iter()
                .all(|&j| set.neighbors_of(j).contains(&i))
        })
    }

    #[test]
    fn knn_is_symmetric_and_contains_the_k_nearest() {
        // A noisy arc.
        let list: Vec<[f64; 2]> = (0..200)
            .map(|i| {
                let t = i as f64 * 0.03;
                let jitter = ((i * 7919) % 13) as f64 * 0.01;
                [100.0 * t.cos() + jitter, 100.0 * t.sin() - jitter]
            })
            .collect();
        let params = Params::default();
        let set = point_set(&list, &params).unwrap();
        set.validate().unwrap();
        assert!(is_symmetric(&set));
        for i in 0..set.len() {
            let p = set.points[i];
            let mut by_distance: Vec<(f64, usize)> = (0..set.len())
                .filter(|&j| j != i)
                .map(|j| ((set.points[j][0] - p[0]).hypot(set.points[j][1] - p[1]), j))
                .collect();
            by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
            let neighbours = set.neighbors_of(i as u32);
            assert!(neighbours.len() >= params.method.k);
            for &(_, j) in &by_distance[..params.method.k] {
                assert!(neighbours.contains(&(j as u32)), "point {i} misses {j}");
            }
            // Sorted, no duplicates.
            assert!(neighbours.windows(2).all(|w| w[0] < w[1]));
        }
        let mean_nn: f64 = (0..set.len())
            .map(|i| {
                let p = set.points[i];
                (0..set.len())
                    .filter(|&j| j != i)
                    .map(|j| (set.points[j][0] - p[0]).hypot(set.points[j][1] - p[1]))
                    .fold(f64::INFINITY, f64::min)
            })
            .sum::<f64>()
            / set.len() as f64;
        assert!((set.spacing - mean_nn).abs() < 1e-9);
    }

    #[test]
    fn tiny_collinear_and_duplicate_inputs() {
        let params = Params::default();
        let empty = point_set(&[], &params).unwrap();
        assert!(empty.is_empty());
        empty.validate().unwrap();
        let one = point_set(&[[3.0, -4.0]], &params).unwrap();
        one.validate().unwrap();
        assert_eq!(one.half_width, vec![1.0]);
        let two = point_set(&[[0.0, 0.0], [0.0, 2.0]], &params).unwrap();
        two.validate().unwrap();
        assert_eq!(two.neighbors_of(0), &[1]);
        assert_eq!(two.spacing, 2.0);
        // Collinear with repeats and -0.0: duplicates go, first occurrence order kept.
        let mut line: Vec<[f64; 2]> = (0..50).map(|i| [i as f64, 0.0]).collect();
        line.push([3.0, -0.0]);
        line.push([7.0, 0.0]);
        line.insert(0, [49.0, 0.0]);
        let set = point_set(&line, &params).unwrap();
        set.validate().unwrap();
        assert_eq!(set.len(), 50);
        assert_eq!(set.points[0], [49.0, 0.0]);
        assert_eq!(set.points[1], [0.0, 0.0]);
        assert_eq!(set.spacing, 1.0);
        assert!(set.half_width.iter().all(|&h| h == 1.0));
        // All points at one spot.
        let same = point_set(&[[5.0, 5.0]; 10], &params).unwrap();
        assert_eq!(same.len(), 1);
        // Non-finite input is refused.
        assert!(matches!(
            point_set(&[[0.0, f64::NAN]], &params),
            Err(Error::PointParse { line: 1, .. })
        ));
    }

    #[test]
    fn large_and_negative_coordinates_keep_their_values() {
        let list: Vec<[f64; 2]> = (0..30).map(|i| [-1e9 + i as f64 * 0.5, 1e9]).collect();
        let set = point_set(&list, &Params::default()).unwrap();
        assert_eq!(set.points, list);
        assert!((set.spacing - 0.5).abs() < 1e-6);
        assert!(set.half_width.iter().all(|&h| (h - 0.5).abs() < 1e-6));
        let mut params = Params::default();
        params.front_end.limits.max_points = 10;
        assert!(matches!(
            point_set(&list, &params),
            Err(Error::Limit { .. })
        ));
    }

    #[test]
    fn half_width_of_pixel_centers_matches_the_image_path() {
        // A 5-px bar as pixel centers: center row 3, edges 1.
        let list: Vec<[f64; 2]> = (0..5)
            .flat_map(|y| (0..40).map(move |x| [x as f64 + 0.5, y as f64 + 10.5]))
            .collect();
        let mut params = Params::default();
        params.front_end.dropout = Some(false);
        let set = point_set(&list, &params).unwrap();
        let at = |x: usize, y: usize| set.half_width[y * 40 + x];
        assert_eq!(at(20, 2), 3.0);
        assert_eq!(at(20, 0), 1.0);
        assert_eq!(at(20, 1), 2.0);
        // The sparse search gives the same values as the dense raster.
        let cells: Vec<(i64, i64)> = list
            .iter()
            .map(|p| ((p[0] - 0.5) as i64, (p[1] - 10.5) as i64))
            .collect();
        assert_eq!(sparse_half_widths(&cells, 1.0), set.half_width);
    }

    #[test]
    fn sparse_half_widths_equal_the_dense_raster_on_scattered_points() {
        // Random points in a band 9 units wide and in a few clumps: cells with empty cells at
        // every distance, some far inside.
        let mut rng = crate::test_rng::XorShift::new(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.unit();
        let mut list: Vec<[f64; 2]> = (0..3000)
            .map(|_| [next() * 300.0, 20.0 + next() * 9.0])
            .collect();
        list.extend((0..2000).map(|_| [150.0 + next() * 12.0, 30.0 + next() * 12.0]));
        let mut params = Params::default();
        params.front_end.dropout = Some(false);
        let dense = half_widths(&list, 1.0, &params);
        let cells: Vec<(i64, i64)> = list
            .iter()
            .map(|p| ((p[0] + 0.5).floor() as i64, (p[1] + 0.5).floor() as i64))
            .collect();
        assert!(dense.iter().any(|&h| h >= 3.0));
        assert_eq!(sparse_half_widths(&cells, 1.0), dense);
    }
}
