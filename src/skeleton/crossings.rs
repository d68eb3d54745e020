//! Crossings: the method's crossings decide which skeleton junctions are one vertex
//! ([`Work::merge_crossings`]); junctions closer than the ink can show apart are one
//! ([`Work::contract_short_links`]); crossings the method did not see, of two strokes
//! ([`Work::merge_split_crossings`]) or more ([`Work::merge_split_stars`]), are found from the
//! straightness of their arms; arms run straight into their junction
//! ([`Work::straighten_junctions`]). docs/design.md, "Skeleton-carried geometry".

use std::cell::OnceCell;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use petgraph::unionfind::UnionFind;

use std::cmp::Ordering;

use crate::geometry::{cmp_dist, dist, dist_bounds, hypot, line_intersection, unit};
use crate::stroke_graph::{Edge, StrokeGraph, Vertex};

use super::disk_radius;
use super::work::{cut_arm, cut_point, median, points_outwards, Ink, Work};

/// A crossing owns the skeleton junctions within this many of its widths: the Y's of an acute
/// crossing lie about `(w / 2) / sin(θ / 2)` from it, 3.8 w at 15 degrees, and the method's
/// width at a crossing can be a little less than the strokes'.
const CROSSING_REACH: f64 = 5.0;

/// The narrowest width (px) a crossing's reach is measured in: a crossing of hairlines still
/// owns the Y's thinning makes a pixel or two from it.
const MIN_CROSSING_WIDTH_PX: f64 = 2.0;

/// A crossing's junctions are linked by edges at most this many reaches long: two junctions
/// within the reach lie at most twice it apart.
const LINK_REACHES: f64 = 2.0;

/// A crossing's arms bend towards the skeleton's Y's within about this many widths of them:
/// they are cut that far beyond the farthest Y.
const ARM_BEND: f64 = 0.5;

/// The reach of a crossing (px): [`CROSSING_REACH`] of its widths.
fn crossing_reach(c: &Vertex) -> f64 {
    CROSSING_REACH * c.width.max(MIN_CROSSING_WIDTH_PX)
}

/// Two junctions linked by at most this many of the link's widths are one: thinning splits a
/// crossing of strokes into two Y's closer than half a width.
const SHORT_LINK: f64 = 0.5;

/// See [`SHORT_LINK`] (px): thinning splits a crossing of thin strokes into two Y's a pixel or
/// two apart.
const SHORT_LINK_PX: f64 = 3.0;

impl Work {
    /// Crossings: around each of the method's vertices of degree >= 4, the skeleton junctions
    /// nearer to it than to any other of the method's junctions and within 5 of its widths,
    /// linked by short skeleton edges (at most that radius) that form a tree (no hole among
    /// them), and leaving by exactly as many arms as the crossing has, become one vertex at the
    /// crossing. A long edge between two of them (the loop of an `8` closing on its waist)
    /// becomes a loop at the crossing. Each arm is cut where it leaves the merged junctions'
    /// reach and joined straight to the crossing. Two junctions whose arms show two T's on one
    /// stroke ([`Work::offset_tees`]), or a T whose stem is the link ([`Work::tee_on_a_stroke`]),
    /// stay two.
    pub(super) fn merge_crossings(&mut self, method: &StrokeGraph) {
        let junctions: Vec<&Vertex> = method.vertices.iter().filter(|v| v.degree >= 3).collect();
        if !junctions.iter().any(|v| v.degree >= 4) {
            return;
        }
        let mut degree = self.degrees();
        let mut at = self.incidence();
        let Some(owned) = self.crossing_owners(&junctions, &degree) else {
            return;
        };
        let mut mark = vec![usize::MAX; self.vertices.len()];
        for (owner, near) in owned.iter().enumerate() {
            if near.len() < 2 {
                continue;
            }
            let c = junctions[owner];
            for &i in near {
                mark[i] = owner;
            }
            let linked = self.linked_group(c, near, |v| mark[v] == owner, &at);
            for &i in near {
                mark[i] = usize::MAX;
            }
            let Some((group, links)) = linked else {
                continue;
            };
            if group.len() < 2 {
                continue;
            }
            let Some(internal) = self.spanning_links(&group, links) else {
                continue;
            };
            let arms: usize = group.iter().map(|&i| degree[i]).sum::<usize>() - 2 * internal.len();
            if arms != c.degree {
                continue;
            }
            if let (&[a, b], &[link]) = (&group[..], &internal[..]) {
                if self.offset_tees(link, a, b, &at) || self.tee_on_a_stroke(link, a, b, &at) {
                    continue;
                }
                if self.stems_apart(a, b, &at, true) == Some(true) {
                    continue;
                }
                if self.side_by_side(link, a, b, &at) {
                    continue;
                }
            }
            // A star split by thinning (a stroke starting at a crossing forks off where the
            // inks part) is one vertex, even where a stroke runs straight beside the method's
            // star.
            let star = internal.iter().all(|&e| {
                self.edges[e].as_ref().is_some_and(|edge| {
                    self.stems_apart(edge.from, edge.to, &at, false) == Some(false)
                })
            });
            if !star && self.stroke_beside(c, &group, &at) {
                continue;
            }
            let Some(reach) = self.arm_reach(c, &group, &internal, &at) else {
                continue;
            };
            self.merge_into_hub(c, &group, &internal, reach, &mut at, &mut degree);
            degree[group[0]] = arms;
        }
    }

    /// The skeleton junctions each crossing owns: those whose nearest junction of the method
    /// (in `junctions`) is a crossing, within its reach. `None` when the junctions cannot be
    /// indexed.
    fn crossing_owners(&self, junctions: &[&Vertex], degree: &[usize]) -> Option<Vec<Vec<usize>>> {
        let positions: Vec<[f64; 2]> = junctions.iter().map(|v| v.pos).collect();
        let tree = ImmutableKdTree::<f64, 2>::new_from_slice(&positions).ok()?;
        let mut owned: Vec<Vec<usize>> = vec![Vec::new(); junctions.len()];
        for i in (0..self.vertices.len()).filter(|&i| self.alive[i] && degree[i] >= 3) {
            let nearest = tree
                .query(&self.vertices[i].pos)
                .nearest_one::<SquaredEuclidean<f64>>()
                .execute();
            let owner = nearest.item as usize;
            let c = junctions[owner];
            if c.degree >= 4 && dist(self.vertices[i].pos, c.pos) <= crossing_reach(c) {
                owned[owner].push(i);
            }
        }
        Some(owned)
    }

    /// The skeleton junctions linked to the one of `near` nearest the crossing `c` by edges
    /// among the junctions `owned` ([`LINK_REACHES`] reaches long at most: two junctions within
    /// the reach), and the links.
    fn linked_group(
        &self,
        c: &Vertex,
        near: &[usize],
        owned: impl Fn(usize) -> bool,
        at: &[Vec<usize>],
    ) -> Option<(Vec<usize>, Vec<usize>)> {
        let length = Edge::length;
        let radius = crossing_reach(c);
        let &seed = near.iter().min_by(|&&a, &&b| {
            dist(self.vertices[a].pos, c.pos)
                .total_cmp(&dist(self.vertices[b].pos, c.pos))
                .then(a.cmp(&b))
        })?;
        let mut group = vec![seed];
        let mut links: Vec<usize> = Vec::new();
        let mut next = 0;
        while next < group.len() {
            let g = group[next];
            next += 1;
            for &e in &at[g] {
                let Some(edge) = &self.edges[e] else { continue };
                let other = if edge.from == g { edge.to } else { edge.from };
                if other == g || !owned(other) || length(edge) > LINK_REACHES * radius {
                    continue;
                }
                if !links.contains(&e) {
                    links.push(e);
                }
                if !group.contains(&other) {
                    group.push(other);
                }
            }
        }
        Some((group, links))
    }

    /// The shortest links that join the group (Kruskal), to be merged away; `None` when a link
    /// would close a cycle: it goes round a hole among the junctions (a cell of a grid), so they
    /// are not one crossing. (A longer edge between two of them, the loop of an `8`, is no link
    /// and stays, as a loop at the crossing.)
    fn spanning_links(&self, group: &[usize], mut links: Vec<usize>) -> Option<Vec<usize>> {
        let length = Edge::length;
        links.sort_by(|&a, &b| {
            let (la, lb) = (
                self.edges[a].as_ref().map_or(0.0, length),
                self.edges[b].as_ref().map_or(0.0, length),
            );
            la.total_cmp(&lb).then(a.cmp(&b))
        });
        let mut union = UnionFind::<usize>::new(group.len());
        let slot = |v: usize| group.iter().position(|&g| g == v).unwrap_or(0);
        let mut internal = Vec::new();
        for &e in &links {
            let Some(edge) = &self.edges[e] else { continue };
            if union.union(slot(edge.from), slot(edge.to)) {
                internal.push(e);
            }
        }
        (internal.len() == links.len()).then_some(internal)
    }

    /// Where the arms of the crossing `c` are cut: they bend towards the skeleton's Y's within
    /// about [`ARM_BEND`] widths of them, so they are cut beyond that and run straight to the
    /// crossing, or just beyond the Y's where that line would leave the ink; `None` where both
    /// would: this is no crossing.
    fn arm_reach(
        &self,
        c: &Vertex,
        group: &[usize],
        internal: &[usize],
        at: &[Vec<usize>],
    ) -> Option<f64> {
        let spread = group
            .iter()
            .map(|&i| dist(self.vertices[i].pos, c.pos))
            .fold(0.0f64, f64::max);
        let arms_hold = |reach: f64| {
            group.iter().all(|&i| {
                at[i].iter().all(|&e| {
                    let Some(edge) = self.edges[e].as_ref() else {
                        return true;
                    };
                    if internal.contains(&e) {
                        return true;
                    }
                    let ends = [edge.from == i, edge.to == i];
                    ends.iter().enumerate().all(|(end, &here)| {
                        if !here {
                            return true;
                        }
                        self.ink
                            .holds_thin(c.pos, cut_point(edge, end == 0, c.pos, reach), c.width)
                    })
                })
            })
        };
        [spread + ARM_BEND * c.width, spread]
            .into_iter()
            .find(|&r| arms_hold(r))
    }

    /// Makes the group one vertex (its first) at the crossing `c`: the `internal` links go, every
    /// other edge of the group's is moved to it and cut at `reach`; `at` and `degree` follow,
    /// but the hub's degree, which the caller knows.
    fn merge_into_hub(
        &mut self,
        c: &Vertex,
        group: &[usize],
        internal: &[usize],
        reach: f64,
        at: &mut [Vec<usize>],
        degree: &mut [usize],
    ) {
        for &e in internal {
            self.edges[e] = None;
        }
        let hub = group[0];
        self.vertices[hub].pos = c.pos;
        self.vertices[hub].width = c.width;
        let mut hub_edges = Vec::new();
        for &i in group {
            if i != hub {
                self.alive[i] = false;
            }
            for &e in &at[i] {
                let Some(edge) = self.edges[e].as_mut() else {
                    continue;
                };
                if hub_edges.contains(&e) {
                    continue;
                }
                hub_edges.push(e);
                for end in 0..2 {
                    let at_end = if end == 0 { edge.from } else { edge.to };
                    if !group.contains(&at_end) {
                        continue;
                    }
                    if end == 0 {
                        edge.from = hub;
                    } else {
                        edge.to = hub;
                    }
                    cut_arm(edge, end == 0, c.pos, reach);
                }
            }
            if i != hub {
                at[i].clear();
                degree[i] = 0;
            }
        }
        at[hub] = hub_edges;
    }

    /// Whether one of the skeleton junctions `group` is a crossing of its own beside the
    /// method's crossing `c`: it has four or more edges, two of which (arms or links) leave it
    /// in opposite directions within [`STROKE_THROUGH_SINE`], each measured over one width from
    /// where it leaves the junction's disk, and `c` lies farther than half a width
    /// ([`disk_radius`]) from that stroke's line, or on it but where a steep third edge
    /// ([`MIN_STEM_SINE`]), followed straight, meets it a width or more away. The ink shows
    /// that stroke running through the junction and not through `c`: the neighbouring
    /// crossings of a grid whose cells are finer than the method's disks (docs/quality.md,
    /// "Crossings of grids and script, again (issue 31)"). Junctions of degree 3 are left to
    /// [`Work::offset_tees`] and [`Work::tee_on_a_stroke`]: on them the test also split
    /// crossings of script loops.
    fn stroke_beside(&self, c: &Vertex, group: &[usize], at: &[Vec<usize>]) -> bool {
        let cross = |u: [f64; 2], v: [f64; 2]| u[0] * v[1] - u[1] * v[0];
        group.iter().any(|&j| {
            let jp = self.vertices[j].pos;
            // Each edge leaving `j`: where it leaves the junction's disk, its direction on
            // from there and its median width.
            let mut arms: Vec<([f64; 2], [f64; 2], f64)> = Vec::new();
            for &e in &at[j] {
                let Some(edge) = self.edges[e].as_ref() else {
                    continue;
                };
                for (here, forward) in [(edge.from == j, true), (edge.to == j, false)] {
                    if !here {
                        continue;
                    }
                    let w = median(&edge.widths);
                    let outwards = points_outwards(edge, forward);
                    let near = point_at_distance(&outwards, jp, disk_radius(w));
                    let far = point_at_distance(&outwards, jp, disk_radius(w) + SPLIT_NEAR * w);
                    if dist(near, far) < MIN_SPLIT_LINE_PX {
                        continue;
                    }
                    if let Some(u) = unit([far[0] - near[0], far[1] - near[1]]) {
                        arms.push((near, u, w));
                    }
                }
            }
            if arms.len() < 4 {
                return false;
            }
            arms.iter().enumerate().any(|(k, &(p, u, wu))| {
                arms[k + 1..].iter().any(|&(q, v, wv)| {
                    let opposite =
                        u[0] * v[0] + u[1] * v[1] < 0.0 && cross(u, v).abs() <= STROKE_THROUGH_SINE;
                    let Some(d) = unit([u[0] - v[0], u[1] - v[1]]).filter(|_| opposite) else {
                        return false;
                    };
                    // The stroke's line: through the middle of where the two edges leave the
                    // junction's disk (the junction itself may sit a pixel off it).
                    let middle = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                    let w = wu.min(wv);
                    let to_c = [c.pos[0] - middle[0], c.pos[1] - middle[1]];
                    if cross(to_c, d).abs() > disk_radius(w) {
                        return true;
                    }
                    // The crossing on the stroke, but a third edge leaving it steeply,
                    // followed straight back from its own stretch, meets the stroke a width or
                    // more from the crossing: a T of its own ([`Work::offset_tees`]). The Y's
                    // third arm of a split crossing, followed so, meets it at the crossing.
                    arms.iter().any(|&(r, t, _)| {
                        cross(t, d).abs() > MIN_STEM_SINE
                            && line_intersection(&[(middle, d), (r, t)], 0.0).is_some_and(|m| {
                                let along = (c.pos[0] - m[0]) * d[0] + (c.pos[1] - m[1]) * d[1];
                                along.abs() >= TEES_APART * w
                            })
                    })
                })
            })
        })
    }

    /// Whether the linked skeleton junctions `j` and `k` are junctions of their own, by where
    /// their strokes meet the line through them: every edge leaving either (but those joining
    /// them), measured over one width from where it leaves the junction's disk as
    /// [`Work::stroke_beside`] measures, runs along that line (within
    /// [`STROKE_THROUGH_SINE`]: the stroke they share), leaves it too shallowly to meet it
    /// anywhere definite ([`MIN_TEE_SINE`]), or, followed straight back, meets it.
    /// `Some(true)` when every meeting point of `j`'s edges lies at least [`TEES_APART`]
    /// widths from every one of `k`'s, `Some(false)` when some pair lies closer, `None` when
    /// either junction has none. The width is the widest of the edges' median widths: the
    /// truth joins junctions closer than the widest stroke at them (docs/quality.md, "The
    /// truth as the ink shows it, where strokes crowd").
    ///
    /// With `steep` (two degree-3 junctions, the frame T's of a grid whose arms are too short
    /// for [`Work::offset_tees`]' stretch), `Some(true)` also asks that both junctions hold
    /// the shared stroke running on along the line, that they lie at least [`TEES_APART`]
    /// widths apart, and that every edge that meets the line leaves it steeply
    /// ([`MIN_STEM_SINE`]; one between 30 and 60 degrees gives `None`): the two Y's of a
    /// crossing leave the link's line at half the crossing's angle either side, and where a
    /// curve crosses a stroke one of them may look straight along it (docs/quality.md,
    /// "Crossings of grids and script, again (issue 31)").
    fn stems_apart(&self, j: usize, k: usize, at: &[Vec<usize>], steep: bool) -> Option<bool> {
        let cross = |u: [f64; 2], v: [f64; 2]| u[0] * v[1] - u[1] * v[0];
        let (jp, kp) = (self.vertices[j].pos, self.vertices[k].pos);
        let d = unit([kp[0] - jp[0], kp[1] - jp[1]])?;
        let mut width = 0.0f64;
        let mut meets: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut along = [false, false];
        for (side, x) in [j, k].into_iter().enumerate() {
            let xp = self.vertices[x].pos;
            for &e in &at[x] {
                let Some(edge) = self.edges[e].as_ref() else {
                    continue;
                };
                if (edge.from == j && edge.to == k) || (edge.from == k && edge.to == j) {
                    continue;
                }
                for (here, forward) in [(edge.from == x, true), (edge.to == x, false)] {
                    if !here {
                        continue;
                    }
                    let w = median(&edge.widths);
                    width = width.max(w);
                    let outwards = points_outwards(edge, forward);
                    let near = point_at_distance(&outwards, xp, disk_radius(w));
                    let far = point_at_distance(&outwards, xp, disk_radius(w) + SPLIT_NEAR * w);
                    if dist(near, far) < MIN_SPLIT_LINE_PX {
                        continue;
                    }
                    let Some(t) = unit([far[0] - near[0], far[1] - near[1]]) else {
                        continue;
                    };
                    let sine = cross(t, d).abs();
                    if sine <= STROKE_THROUGH_SINE {
                        along[side] = true;
                        continue;
                    }
                    if sine <= MIN_TEE_SINE {
                        continue;
                    }
                    if steep && sine <= MIN_STEM_SINE {
                        return None;
                    }
                    let Some(m) = line_intersection(&[(jp, d), (near, t)], 0.0) else {
                        continue;
                    };
                    meets[side].push((m[0] - jp[0]) * d[0] + (m[1] - jp[1]) * d[1]);
                }
            }
        }
        if meets.iter().any(Vec::is_empty) {
            return None;
        }
        let apart = meets[0].iter().all(|&a| {
            meets[1]
                .iter()
                .all(|&b| (a - b).abs() >= TEES_APART * width)
        });
        if steep && apart && !(along[0] && along[1] && dist(jp, kp) >= TEES_APART * width) {
            return None;
        }
        Some(apart)
    }

    /// Two skeleton junctions closer than the ink can show apart (a link of at most
    /// `max(3 px, w / 2)`, `w` its median width): thinning splits a crossing of thin strokes
    /// into two Y's a pixel or two apart. The link is contracted to its middle; a second edge
    /// between the two becomes a loop, so no cycle is lost.
    pub(super) fn contract_short_links(&mut self) {
        let mut degree = self.degrees();
        let mut at = self.incidence();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            let (a, b) = (edge.from, edge.to);
            if a == b || degree[a] < 3 || degree[b] < 3 {
                continue;
            }
            let length = edge.length();
            if length > (SHORT_LINK * median(&edge.widths)).max(SHORT_LINK_PX) {
                continue;
            }
            let middle = {
                let (p, q) = (self.vertices[a].pos, self.vertices[b].pos);
                [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0]
            };
            self.edges[e] = None;
            let moved: Vec<usize> = at[b].clone();
            for &o in &moved {
                let Some(other) = self.edges[o].as_mut() else {
                    continue;
                };
                if other.from == b {
                    other.from = a;
                }
                if other.to == b {
                    other.to = a;
                }
            }
            for &o in at[a].iter().chain(&moved) {
                let Some(other) = self.edges[o].as_mut() else {
                    continue;
                };
                if other.from == a {
                    other.points[0] = middle;
                }
                if other.to == a {
                    let last = other.points.len() - 1;
                    other.points[last] = middle;
                }
            }
            let width = self.vertices[a].width.max(self.vertices[b].width);
            self.vertices[a].pos = middle;
            self.vertices[a].width = width;
            self.alive[b] = false;
            degree[a] = degree[a] + degree[b] - 2;
            degree[b] = 0;
            let mut joined = std::mem::take(&mut at[a]);
            joined.extend(moved);
            joined.retain(|&o| o != e);
            joined.sort_unstable();
            joined.dedup();
            at[a] = joined;
            at[b].clear();
        }
    }

    /// Inside a junction's own disk the skeleton's pixel paths bend towards whichever junction
    /// pixel they touch, so arms can cross there: each arm is cut where it leaves the disk (radius
    /// the half-width at the junction) and joined straight to the junction.
    pub(super) fn straighten_junctions(&mut self) {
        let degree = self.degrees();
        for edge in self.edges.iter_mut().flatten() {
            for at_start in [true, false] {
                let v = if at_start { edge.from } else { edge.to };
                if degree[v] < 3 {
                    continue;
                }
                let hub = self.vertices[v].pos;
                let reach = disk_radius(self.vertices[v].width);
                if (edge.from == edge.to || edge.points.len() > 2)
                    && self.ink.holds(hub, cut_point(edge, at_start, hub, reach))
                {
                    cut_arm(edge, at_start, hub, reach);
                }
            }
        }
    }
}

/// A split crossing's arms are measured from this many stroke widths from their junction (beyond
/// the skeleton's bend into its Y) ...
const SPLIT_NEAR: f64 = 1.0;

/// ... to this many (or the arm's end): a stretch short enough to be straight on a loop.
const SPLIT_FAR: f64 = 3.0;

/// Two arms, one at each of two linked junctions, leaving within this angle (degrees) of one
/// direction are two strokes side by side ([`Work::side_by_side`]).
const SIDE_BY_SIDE_DEG: f64 = 30.0;

/// An arm's stretch gives a line when at least this long (px).
const MIN_SPLIT_LINE_PX: f64 = 2.0;

/// Two strokes that meet a third at least this many stroke widths apart are two T's, not one
/// crossing ([`Work::offset_tees`]): their inks meet the third stroke's side by side, with the
/// third stroke's own ink between them, where the two halves of one crossing stroke, each
/// followed straight, meet it at one point, to within the pixel their lines are known to.
const TEES_APART: f64 = 1.0;

/// An arm followed straight meets a stroke only when it leaves it at more than this sine (30
/// degrees): a shallower arm's meeting point slides along the stroke with every pixel of its
/// line.
const MIN_TEE_SINE: f64 = 0.5;

/// A stroke's curve through a split crossing turns no tighter than this many stroke widths of
/// radius: the curve's own ink would fill a tighter turn.
const MIN_ARC_RADIUS: f64 = 1.5;

/// Two degree-3 junctions joined by a link at most this many widths (the narrowest arm's) long
/// may be one crossing by where their arms meet ([`Work::close_crossing`]): thinning's Y's of a
/// crossing at 60-90 degrees lie `w / sin(θ / 2)` apart, 1.4 widths at 90.
const CLOSE_LINK: f64 = 1.0;

/// Where two close junctions' arms meet ([`Work::close_crossing`]) is measured on each arm from
/// this many widths from its junction (where the skeleton's bend into the Y ends, [`ARM_BEND`])
/// ...
const CLOSE_NEAR: f64 = 0.5;

/// ... to this many: a script stroke curls within a few widths of a crossing.
const CLOSE_FAR: f64 = 1.5;

/// A split crossing with a tail ([`Work::tipped_crossing`]) has a link at most this many times
/// `w / sin(θ / 2)` long, where thinning puts the Y's of strokes `w` wide crossing at `θ`.
const TIPPED_LINK: f64 = 2.0;

/// A curve is followed in steps of this many pixels to find where it crosses another.
const ARC_STEP_PX: f64 = 0.25;

/// A skeleton point is known to a pixel (px): a stretch's direction to a pixel over its length.
const PIXEL_PX: f64 = 1.0;

/// Two edges leaving a junction in opposite directions are one straight stroke through it
/// ([`Work::stroke_beside`]) when they turn from straight by less than this sine (20 degrees):
/// the two Y's of a crossing at up to 40 degrees each hold the link and an arm that straight.
const STROKE_THROUGH_SINE: f64 = 0.34;

/// A stem leaves the stroke through a junction of its own ([`Work::stroke_beside`]) when it
/// leaves at more than this sine (60 degrees): the third arm of a split crossing's Y whose link
/// and other arm look straight leaves that line at under 30 degrees, give or take a pixel.
const MIN_STEM_SINE: f64 = 0.87;

/// A curved split crossing's link is at most this many stroke widths long
/// ([`Work::curved_crossing`]): thinning puts the Y's of strokes crossing at `θ` about
/// `w / sin(θ / 2)` apart, 6 widths at 19 degrees; a longer link between curves is a bar, whose
/// offset a curve's bend can hide.
const CURVED_LINK: f64 = 6.0;

/// Three points nearer a line than this (px) are on one: a curve through them is straight.
const COLLINEAR_PX: f64 = 1e-6;

/// The curve of constant curvature through three points, from the first through the second to
/// the third: a circle's arc, or a segment where they are collinear.
enum StrokeArc {
    Circle {
        center: [f64; 2],
        radius: f64,
        /// The start angle and the signed angle swept to the end.
        start: f64,
        sweep: f64,
    },
    Line {
        from: [f64; 2],
        to: [f64; 2],
    },
}

impl StrokeArc {
    /// The curve through `a`, `m` and `b`; `None` when two of them coincide.
    fn through(a: [f64; 2], m: [f64; 2], b: [f64; 2]) -> Option<StrokeArc> {
        if dist(a, m) == 0.0 || dist(m, b) == 0.0 || dist(a, b) == 0.0 {
            return None;
        }
        let (ax, ay) = (a[0] - m[0], a[1] - m[1]);
        let (bx, by) = (b[0] - m[0], b[1] - m[1]);
        let cross = ax * by - ay * bx;
        if cross.abs() <= COLLINEAR_PX * dist(a, b) {
            return Some(StrokeArc::Line { from: a, to: b });
        }
        // The circumcentre, relative to `m`.
        let (a2, b2) = (ax * ax + ay * ay, bx * bx + by * by);
        let ux = (by * a2 - ay * b2) / (2.0 * cross);
        let uy = (ax * b2 - bx * a2) / (2.0 * cross);
        let center = [m[0] + ux, m[1] + uy];
        let angle = |p: [f64; 2]| (p[1] - center[1]).atan2(p[0] - center[0]);
        let tau = std::f64::consts::TAU;
        let (start, through, end) = (angle(a), angle(m), angle(b));
        // Counter-clockwise from `a` to `b` when that passes `m`, else clockwise.
        let ccw = |x: f64| (x - start).rem_euclid(tau);
        let sweep = if ccw(through) <= ccw(end) {
            ccw(end)
        } else {
            ccw(end) - tau
        };
        Some(StrokeArc::Circle {
            center,
            radius: hypot(ux, uy),
            start,
            sweep,
        })
    }

    fn radius(&self) -> f64 {
        match self {
            StrokeArc::Circle { radius, .. } => *radius,
            StrokeArc::Line { .. } => f64::INFINITY,
        }
    }

    /// The signed distance from `p` to the curve's circle or line (positive on one side).
    fn signed(&self, p: [f64; 2]) -> f64 {
        match self {
            StrokeArc::Circle { center, radius, .. } => dist(p, *center) - radius,
            StrokeArc::Line { from, to } => {
                let d = [to[0] - from[0], to[1] - from[1]];
                ((p[0] - from[0]) * d[1] - (p[1] - from[1]) * d[0]) / hypot(d[0], d[1])
            }
        }
    }

    fn distance(&self, p: [f64; 2]) -> f64 {
        self.signed(p).abs()
    }

    /// The curve's length, px.
    fn length(&self) -> f64 {
        match self {
            StrokeArc::Circle { radius, sweep, .. } => radius * sweep.abs(),
            StrokeArc::Line { from, to } => dist(*from, *to),
        }
    }

    /// The point at the share `t` of the way from the curve's start to its end.
    fn at(&self, t: f64) -> [f64; 2] {
        match self {
            StrokeArc::Circle {
                center,
                radius,
                start,
                sweep,
            } => {
                let a = start + t * sweep;
                [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
            }
            StrokeArc::Line { from, to } => [
                from[0] + t * (to[0] - from[0]),
                from[1] + t * (to[1] - from[1]),
            ],
        }
    }

    /// Points along the curve from its start to its end, at most `step` px apart.
    fn samples(&self, step: f64) -> Vec<[f64; 2]> {
        let n = (self.length() / step).ceil().max(1.0) as usize;
        (0..=n).map(|k| self.at(k as f64 / n as f64)).collect()
    }
}

/// The arms of a junction, each with its median width ([`Work::arm_lines`]).
type Arms = Vec<(f64, ArmLine)>;

/// One arm's stretch at a junction: its anchors nearest to and farthest from the junction.
struct ArmLine {
    near: [f64; 2],
    far: [f64; 2],
}

impl Work {
    /// Split crossings the method did not see: two degree-3 skeleton junctions `a` and `b`
    /// joined by an edge (the link) are one crossing when their four arms pair up as two straight
    /// strokes through the link: for each pair (one arm at `a`, one at `b`), the line through
    /// the two arms' far anchors (`SPLIT_FAR` widths out) passes within half a stroke width of
    /// both near anchors (`SPLIT_NEAR` widths out) and lies on the ink, and the two lines meet
    /// on the ink within half a width of the link. Where two strokes cross at a shallow angle,
    /// thinning puts the Y's about `(w / 2) / sin(θ / 2)` either side of the crossing (5.7 w at
    /// 10 degrees), beyond the reach of the method's crossing ([`CROSSING_REACH`]) or where the
    /// method sees none; a bar between two forks ('>-<') has arms whose lines run apart or off
    /// its ink. The pair becomes one vertex where the lines meet, as [`Work::merge_crossings`]
    /// merges. A pair these tests leave is one crossing when the ink prefers it
    /// ([`Work::ink_decides_crossing`]).
    pub(super) fn merge_split_crossings(&mut self, close: bool) {
        // Found only when the ink is asked to decide a pair: most windows never need it.
        let holes = OnceCell::new();
        let mut degree = self.degrees();
        let mut at = self.incidence();
        for link in 0..self.edges.len() {
            let Some(edge) = &self.edges[link] else {
                continue;
            };
            let (a, b) = (edge.from, edge.to);
            if a == b || degree[a] != 3 || degree[b] != 3 || at[a].len() < 2 || at[b].len() < 2 {
                continue;
            }
            let c = self
                .split_crossing(link, a, b, &at)
                .or_else(|| self.ink_decides_crossing(link, a, b, &at, &holes))
                .or_else(|| {
                    close
                        .then(|| self.close_crossing(link, a, b, &at))
                        .flatten()
                });
            let Some(c) = c else {
                continue;
            };
            let (group, internal) = ([a, b], [link]);
            let Some(reach) = self.arm_reach(&c, &group, &internal, &at) else {
                continue;
            };
            self.merge_into_hub(&c, &group, &internal, reach, &mut at, &mut degree);
            degree[a] = 4;
        }
    }

    /// The crossing of the link `link` between the junctions `a` and `b` (see
    /// [`Work::merge_split_crossings`]), or `None`.
    fn split_crossing(&self, link: usize, a: usize, b: usize, at: &[Vec<usize>]) -> Option<Vertex> {
        let Some((arms_a, arms_b, stroke, tolerance)) = self.link_arms(link, a, b, at) else {
            return self.tipped_crossing(link, a, b, at);
        };
        let pairs = [[(0, 0), (1, 1)], [(0, 1), (1, 0)]];
        let Some(&[(i, j), (k, l)]) = pairs.iter().find(|pair| {
            pair.iter().all(|&(i, j)| {
                self.stroke_miss(&arms_a[i].1, &arms_b[j].1, stroke)
                    .is_some()
            })
        }) else {
            return self.curved_crossing(link, &arms_a, &arms_b, stroke, tolerance);
        };
        // Where the two strokes' lines meet (`None` when parallel).
        let lines = [
            stroke_line(&arms_a[i].1, &arms_b[j].1)?,
            stroke_line(&arms_a[k].1, &arms_b[l].1)?,
        ];
        let hub = line_intersection(&lines, 0.0)?;
        self.crossing_at(hub, link, tolerance, stroke)
    }

    /// The crossing of two degree-3 junctions `a` and `b` joined by a short `link` (at most
    /// [`CLOSE_LINK`] of the narrowest arm's width) whose own junctions the ink puts less than
    /// [`TEES_APART`] widths apart: each junction's two other arms, followed straight from
    /// their stretches ([`Work::ink_arms`]: one to three widths out, or what the arm has), meet
    /// where that junction's strokes meet; where both meeting points lie on the ink, on the
    /// link (within half a width), closer than a width to each other, the two junctions are
    /// one vertex, at the middle of the two. Thinning splits a steep crossing of script
    /// strokes into two Y's a width apart whose arms curve too soon for a straight or curved
    /// pairing ([`Work::split_crossing`]) and whose drawings the ink does not tell apart
    /// ([`Work::ink_crossing`]): the Y's of one crossing have arms meeting at the crossing,
    /// the two T's of two strokes ending on a third side by side have stems meeting it where
    /// they do, as far apart as the truth keeps them. Arms leaving a junction nearly straight
    /// through it (a T whose stem is the link) meet nowhere: no crossing (docs/quality.md,
    /// "Session of 2026-12-06, eighth: junctions and crossings in script (issue 31)").
    fn close_crossing(&self, link: usize, a: usize, b: usize, at: &[Vec<usize>]) -> Option<Vertex> {
        let arms_a = self.close_arms(a, link, at)?;
        let arms_b = self.close_arms(b, link, at)?;
        let stroke = arms_a
            .iter()
            .chain(&arms_b)
            .map(|arm| arm.0)
            .fold(f64::INFINITY, f64::min);
        let link_edge = self.edges[link].as_ref()?;
        if link_edge.length() > CLOSE_LINK * stroke {
            return None;
        }
        let tolerance = disk_radius(stroke);
        let on_link = |m: [f64; 2]| {
            link_edge
                .points
                .windows(2)
                .map(|s| crate::geometry::segment_dist(m, s[0], s[1]))
                .fold(f64::INFINITY, f64::min)
                <= tolerance
        };
        let meet = |arms: &Arms| -> Option<[f64; 2]> {
            let (p, q) = (&arms[0].1, &arms[1].1);
            let u = unit([p.near[0] - p.far[0], p.near[1] - p.far[1]])?;
            let v = unit([q.near[0] - q.far[0], q.near[1] - q.far[1]])?;
            if (u[0] * v[1] - u[1] * v[0]).abs() <= MIN_TEE_SINE {
                return None;
            }
            let m = line_intersection(&[(p.far, u), (q.far, v)], 0.0)?;
            (self.ink.at(m) && on_link(m)).then_some(m)
        };
        let (ma, mb) = (meet(&arms_a)?, meet(&arms_b)?);
        if dist(ma, mb) >= TEES_APART * stroke {
            return None;
        }
        let hub = [(ma[0] + mb[0]) / 2.0, (ma[1] + mb[1]) / 2.0];
        self.crossing_at(hub, link, tolerance, stroke)
    }

    /// The two arms at the degree-3 junction `j` other than `link`, each with its median width
    /// and its stretch from [`CLOSE_NEAR`] to [`CLOSE_FAR`] of that width (or half and all of
    /// what the arm has, when shorter); `None` when not two or a stretch is under
    /// [`MIN_SPLIT_LINE_PX`].
    fn close_arms(&self, j: usize, link: usize, at: &[Vec<usize>]) -> Option<Arms> {
        let arms = self
            .other_arms(j, link, at)?
            .into_iter()
            .map(|(edge, forward)| {
                let (w, _, line) = self.stretch(j, edge, forward, CLOSE_NEAR, CLOSE_FAR)?;
                Some((w, line))
            })
            .collect::<Option<Arms>>()?;
        (arms.len() == 2).then_some(arms)
    }

    /// The ends at the junction `j` of its edges other than `link`, each its edge and whether
    /// the edge starts there (an edge from `j` back to `j` twice); `None` when one of them is
    /// gone.
    fn other_arms(&self, j: usize, link: usize, at: &[Vec<usize>]) -> Option<Vec<(&Edge, bool)>> {
        let mut arms = Vec::new();
        for &e in at[j].iter().filter(|&&e| e != link) {
            let edge = self.edges[e].as_ref()?;
            for (here, forward) in [(edge.from == j, true), (edge.to == j, false)] {
                if here {
                    arms.push((edge, forward));
                }
            }
        }
        Some(arms)
    }

    /// The stretch of `edge` leaving the junction `j` (from its start when `forward`) from
    /// `near` to `far` of its median width, or half and all of what the arm reaches when it is
    /// shorter: that width, the arm's points from the junction outwards and the stretch; `None`
    /// when the stretch is under [`MIN_SPLIT_LINE_PX`].
    fn stretch(
        &self,
        j: usize,
        edge: &Edge,
        forward: bool,
        near: f64,
        far: f64,
    ) -> Option<(f64, Vec<[f64; 2]>, ArmLine)> {
        let jp = self.vertices[j].pos;
        let outwards = points_outwards(edge, forward);
        let w = median(&edge.widths);
        // The largest distance; one no larger than the largest so far by its bounds leaves it.
        let reach = outwards.iter().fold(0.0f64, |reach, &p| {
            if dist_bounds(p, jp).is_some_and(|(_, high)| high < reach) {
                reach
            } else {
                reach.max(dist(p, jp))
            }
        });
        let at_distance = |d: f64| point_at_distance(&outwards, jp, d);
        let line = ArmLine {
            near: at_distance((near * w).min(reach / 2.0)),
            far: at_distance((far * w).min(reach)),
        };
        (dist(line.near, line.far) >= MIN_SPLIT_LINE_PX).then_some((w, outwards, line))
    }

    /// A split crossing one of whose arms is a short tail (a stroke ending a little past the
    /// crossing, as the tails of a script `f`'s loops): an arm that ends within [`SPLIT_FAR`]
    /// widths of its junction, too short for a stretch of its own ([`Work::arm_line`]), gives its
    /// tip, at least a width from the junction, as both anchors: a pair with it is one straight
    /// stroke when the line from the tip through the other arm's far anchor passes within half
    /// a width of that arm's near anchor and lies on the ink ([`Work::stroke_miss`]). The tail's
    /// own skeleton bends into its Y over the width it has, so only its tip says where the
    /// stroke runs. At most one such arm at each junction, and the two pairings are tested as
    /// [`Work::split_crossing`] tests them, straight strokes only; the link must run straight
    /// between the junctions (within half a width of the line through them) and be at most
    /// [`TIPPED_LINK`] times `w / sin(θ / 2)` long (docs/quality.md, "Session of 2026-12-06,
    /// third: crossings (issue 31)").
    fn tipped_crossing(
        &self,
        link: usize,
        a: usize,
        b: usize,
        at: &[Vec<usize>],
    ) -> Option<Vertex> {
        let arms_a = self.tipped_arm_lines(a, link, at)?;
        let arms_b = self.tipped_arm_lines(b, link, at)?;
        let stroke = arms_a
            .iter()
            .chain(&arms_b)
            .map(|(w, _)| *w)
            .fold(f64::INFINITY, f64::min);
        let tolerance = disk_radius(stroke);
        let pairs = [[(0, 0), (1, 1)], [(0, 1), (1, 0)]];
        let &[(i, j), (k, l)] = pairs.iter().find(|pair| {
            pair.iter().all(|&(i, j)| {
                self.stroke_miss(&arms_a[i].1, &arms_b[j].1, stroke)
                    .is_some()
            })
        })?;
        let lines = [
            stroke_line(&arms_a[i].1, &arms_b[j].1)?,
            stroke_line(&arms_a[k].1, &arms_b[l].1)?,
        ];
        let hub = line_intersection(&lines, 0.0)?;
        // Thinning puts the Y's of strokes crossing at `θ` about `w / sin(θ / 2)` apart, joined
        // by a straight link along the strokes' shared ink: a longer link, or one that bends
        // away from the line between its junctions, joins two junctions of their own (a box's
        // corner with a foot, and a kink on its side).
        let [(_, u), (_, v)] = lines;
        let sine_half = ((1.0 - (u[0] * v[0] + u[1] * v[1]).abs()) / 2.0).sqrt();
        let edge = self.edges[link].as_ref()?;
        let (pa, pb) = (self.vertices[a].pos, self.vertices[b].pos);
        let straight = edge
            .points
            .iter()
            .all(|&p| line_dist(p, pa, pb) <= tolerance);
        if !straight || edge.length() * sine_half > TIPPED_LINK * stroke {
            return None;
        }
        self.crossing_at(hub, link, tolerance, stroke)
    }

    /// The two arms at the degree-3 junction `j` other than `link`, as
    /// [`Work::tipped_crossing`] takes them: each its stretch ([`Work::arm_line`]) or, for an
    /// arm ending in an end too near for one, its tip as both anchors; `None` when there are not
    /// two, neither has a stretch, or a tip lies within a width of the junction.
    fn tipped_arm_lines(&self, j: usize, link: usize, at: &[Vec<usize>]) -> Option<Arms> {
        let jp = self.vertices[j].pos;
        let mut arms = Vec::new();
        let mut tips = 0;
        for &e in at[j].iter().filter(|&&e| e != link) {
            let edge = self.edges[e].as_ref()?;
            for (here, forward) in [(edge.from == j, true), (edge.to == j, false)] {
                if !here {
                    continue;
                }
                if let Some(arm) = self.arm_line(j, edge, forward) {
                    arms.push(arm);
                    continue;
                }
                let (other, tip) = if forward {
                    (edge.to, *edge.points.last()?)
                } else {
                    (edge.from, edge.points[0])
                };
                let w = median(&edge.widths);
                if at[other].len() != 1 || other == j || dist(tip, jp) < w.max(MIN_SPLIT_LINE_PX) {
                    return None;
                }
                tips += 1;
                arms.push((
                    w,
                    ArmLine {
                        near: tip,
                        far: tip,
                    },
                ));
            }
        }
        (arms.len() == 2 && tips <= 1).then_some(arms)
    }

    /// The crossing at `hub`, when it lies on the ink within `tolerance` px of the `link` between
    /// the split crossing's two junctions.
    fn crossing_at(
        &self,
        hub: [f64; 2],
        link: usize,
        tolerance: f64,
        stroke: f64,
    ) -> Option<Vertex> {
        let near_link = self.edges[link]
            .as_ref()?
            .points
            .iter()
            .map(|&p| dist(p, hub))
            .fold(f64::INFINITY, f64::min);
        if near_link > tolerance || !self.ink.at(hub) {
            return None;
        }
        Some(Vertex {
            pos: hub,
            degree: 4,
            width: stroke,
        })
    }

    /// A split crossing of curves (a stroke crossing the loop of a ほ, two strokes of a script
    /// loop): where no pairing of the link's arms is two straight strokes, each pair may be one
    /// curve of constant curvature ([`StrokeArc`]: through both far anchors and the middle of
    /// the near anchors, no tighter than [`MIN_ARC_RADIUS`] widths) passing within half a
    /// stroke width of both near anchors, on the ink, bending one way at one rate
    /// ([`one_bend`]: not an S, the offset of two T's or of forks on a bar): as
    /// [`Work::stroke_miss`] asks of a straight stroke, with the curve's own bend allowed. The
    /// link is at most [`CURVED_LINK`] widths long. The crossing is where the two curves
    /// cross, within half a width of the link; two curves that touch without crossing are none.
    fn curved_crossing(
        &self,
        link: usize,
        arms_a: &Arms,
        arms_b: &Arms,
        stroke: f64,
        tolerance: f64,
    ) -> Option<Vertex> {
        let link_points = &self.edges[link].as_ref()?.points;
        if Edge::length(self.edges[link].as_ref()?) > CURVED_LINK * stroke {
            return None;
        }
        let arc = |p: &ArmLine, q: &ArmLine| -> Option<StrokeArc> {
            let middle = [(p.near[0] + q.near[0]) / 2.0, (p.near[1] + q.near[1]) / 2.0];
            let arc = StrokeArc::through(p.far, middle, q.far)?;
            let fits = arc.radius() >= MIN_ARC_RADIUS * stroke
                && arc.distance(p.near) <= tolerance
                && arc.distance(q.near) <= tolerance
                && one_bend(p, q, tolerance)
                && self.ink.holds(p.far, p.near)
                && self.ink.holds(p.near, q.near)
                && self.ink.holds(q.near, q.far);
            fits.then_some(arc)
        };
        let pairs = [[(0, 0), (1, 1)], [(0, 1), (1, 0)]];
        let arcs = pairs.iter().find_map(|pair| {
            let [(i, j), (k, l)] = *pair;
            Some([
                arc(&arms_a[i].1, &arms_b[j].1)?,
                arc(&arms_a[k].1, &arms_b[l].1)?,
            ])
        })?;
        // Where the first curve crosses the second (its signed distance changes sign), the
        // crossing nearest the link's middle.
        let middle = link_points[link_points.len() / 2];
        let samples = arcs[0].samples(ARC_STEP_PX);
        let hub = samples
            .windows(2)
            .filter_map(|s| {
                let (d0, d1) = (arcs[1].signed(s[0]), arcs[1].signed(s[1]));
                if (d0 < 0.0) == (d1 < 0.0) {
                    return None;
                }
                let t = d0 / (d0 - d1);
                Some([
                    s[0][0] + t * (s[1][0] - s[0][0]),
                    s[0][1] + t * (s[1][1] - s[0][1]),
                ])
            })
            .min_by(|&p, &q| dist(p, middle).total_cmp(&dist(q, middle)))?;
        self.crossing_at(hub, link, tolerance, stroke)
    }

    /// Whether the degree-3 junctions `a` and `b`, joined by the edge `link`, are two T's on one
    /// stroke rather than the two Y's thinning makes of one crossing (which
    /// [`Work::merge_crossings`] merges where the method saw a crossing): one arm at `a` and
    /// one at `b` are one straight stroke through the link ([`Work::stroke_miss`]), the other two
    /// are not, and those two, each followed straight from its own stretch, meet the straight
    /// stroke at least [`TEES_APART`] widths apart. The two halves of a crossing stroke meet
    /// the other stroke at one point, however its Y's lie; a curve crossing a straight stroke
    /// too. `false` when the arms do not decide (no straight stroke, both pairs straight, an
    /// arm too short for a line or too shallow to meet the stroke).
    fn offset_tees(&self, link: usize, a: usize, b: usize, at: &[Vec<usize>]) -> bool {
        let Some((arms_a, arms_b, stroke, _)) = self.link_arms(link, a, b, at) else {
            return false;
        };
        let straight = |i: usize, j: usize| {
            self.stroke_miss(&arms_a[i].1, &arms_b[j].1, stroke)
                .is_some()
        };
        if (straight(0, 0) && straight(1, 1)) || (straight(0, 1) && straight(1, 0)) {
            return false;
        }
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            if !straight(i, j) {
                continue;
            }
            let Some((p, d)) = stroke_line(&arms_a[i].1, &arms_b[j].1) else {
                continue;
            };
            // Where an arm, followed straight from its far anchor towards its junction, meets
            // the straight stroke's line.
            let meet = |q: &ArmLine| {
                let u = unit([q.near[0] - q.far[0], q.near[1] - q.far[1]])?;
                let sine = (u[0] * d[1] - u[1] * d[0]).abs();
                (sine > MIN_TEE_SINE)
                    .then(|| line_intersection(&[(p, d), (q.far, u)], 0.0))
                    .flatten()
            };
            if let (Some(at_a), Some(at_b)) = (meet(&arms_a[1 - i].1), meet(&arms_b[1 - j].1)) {
                if dist(at_a, at_b) >= TEES_APART * stroke {
                    return true;
                }
            }
        }
        false
    }

    /// Whether the junctions `a` and `b`, joined by the edge `link`, are two junctions rather
    /// than the two Y's thinning makes of one crossing or star: the link runs at least
    /// [`TEES_APART`] widths, and one of two degree-3 junctions is a T (its two other arms one
    /// straight stroke through it, [`Work::stroke_miss`]; the link is its stem). The two Y's of
    /// a crossing each hold one arm of either stroke, on one side of the crossing: never a
    /// straight stroke through a Y. Where one of them is itself a crossing (degree 4 or more),
    /// both must hold a straight stroke: a T three widths from a grid's crossing, two crossings
    /// of a grid two widths apart. A star of five, one stroke crossing a second where a third
    /// starts, splits into a crossing and a Y whose two arms leave to one side: it stays one.
    /// `false` when an arm is too short for a line; the width is the narrowest of the arms.
    fn tee_on_a_stroke(&self, link: usize, a: usize, b: usize, at: &[Vec<usize>]) -> bool {
        let (Some(arms_a), Some(arms_b)) =
            (self.arm_lines(a, link, at), self.arm_lines(b, link, at))
        else {
            return false;
        };
        let stroke = arms_a
            .iter()
            .chain(&arms_b)
            .map(|(w, _)| *w)
            .fold(f64::INFINITY, f64::min);
        if dist(self.vertices[a].pos, self.vertices[b].pos) < TEES_APART * stroke {
            return false;
        }
        let straight = |arms: &Arms| {
            arms.iter().enumerate().any(|(k, p)| {
                arms[k + 1..]
                    .iter()
                    .any(|q| self.stroke_miss(&p.1, &q.1, stroke).is_some())
            })
        };
        if arms_a.len() == 2 && arms_b.len() == 2 {
            straight(&arms_a) || straight(&arms_b)
        } else {
            straight(&arms_a) && straight(&arms_b)
        }
    }

    /// Whether the arms `p` and `q` of a stroke `stroke` px wide are one straight stroke: the
    /// line through their far anchors lies on the ink ([`Ink::holds_thin`]) and passes within
    /// the stroke's tolerance ([`disk_radius`]) of both near anchors. How far it misses the
    /// farther of them; `None` when they are not.
    fn stroke_miss(&self, p: &ArmLine, q: &ArmLine, stroke: f64) -> Option<f64> {
        let tolerance = disk_radius(stroke);
        let worst = [p.near, q.near]
            .iter()
            .map(|&n| line_dist(n, p.far, q.far))
            .fold(0.0f64, f64::max);
        (worst <= tolerance && self.ink.holds_thin(p.far, q.far, stroke)).then_some(worst)
    }

    /// Whether the degree-3 junctions `a` and `b`, joined by the edge `link`, each have an arm
    /// leaving in one direction (within [`SIDE_BY_SIDE_DEG`]), measured over one of its widths:
    /// two strokes side by side (the rungs of a ladder, the teeth of a comb finer than the
    /// method's disks, an arm beside a stroke's foot), not the halves of one stroke through a
    /// crossing (opposite) nor two strokes crossing on one side of it (apart by the crossing's
    /// angle). `false` when an arm has no direction.
    fn side_by_side(&self, link: usize, a: usize, b: usize, at: &[Vec<usize>]) -> bool {
        let directions = |j: usize| -> Option<Vec<[f64; 2]>> {
            let jp = self.vertices[j].pos;
            self.other_arms(j, link, at)?
                .into_iter()
                .map(|(edge, forward)| {
                    let p = arm_point(edge, forward, jp, median(&edge.widths));
                    unit([p[0] - jp[0], p[1] - jp[1]])
                })
                .collect()
        };
        let (Some(da), Some(db)) = (directions(a), directions(b)) else {
            return false;
        };
        let parallel = SIDE_BY_SIDE_DEG.to_radians().cos();
        da.len() == 2
            && db.len() == 2
            && da
                .iter()
                .any(|u| db.iter().any(|v| u[0] * v[0] + u[1] * v[1] > parallel))
    }

    /// The two other arms at each end of the link `link` between the degree-3 junctions `a`
    /// and `b` ([`Work::arm_lines`]; `None` where either has more), the narrowest of their widths and the tolerance of that width
    /// ([`disk_radius`]) a stroke's line may miss by.
    fn link_arms(
        &self,
        link: usize,
        a: usize,
        b: usize,
        at: &[Vec<usize>],
    ) -> Option<(Arms, Arms, f64, f64)> {
        let arms_a = self.arm_lines(a, link, at).filter(|arms| arms.len() == 2)?;
        let arms_b = self.arm_lines(b, link, at).filter(|arms| arms.len() == 2)?;
        let stroke = arms_a
            .iter()
            .chain(&arms_b)
            .map(|(w, _)| *w)
            .fold(f64::INFINITY, f64::min);
        Some((arms_a, arms_b, stroke, disk_radius(stroke)))
    }

    /// The arms at the junction `j` other than `link`: each its median width and line; `None`
    /// when there are fewer than two or one is too short for a line.
    fn arm_lines(&self, j: usize, link: usize, at: &[Vec<usize>]) -> Option<Arms> {
        let arms = self
            .other_arms(j, link, at)?
            .into_iter()
            .map(|(edge, forward)| self.arm_line(j, edge, forward))
            .collect::<Option<Arms>>()?;
        (arms.len() >= 2).then_some(arms)
    }

    /// The stretch of `edge` leaving the junction `j` (from its start when `forward`) from
    /// [`SPLIT_NEAR`] to [`SPLIT_FAR`] of its median width, with that width; `None` when too
    /// short for a line.
    fn arm_line(&self, j: usize, edge: &Edge, forward: bool) -> Option<(f64, ArmLine)> {
        let jp = self.vertices[j].pos;
        let w = median(&edge.widths);
        let outwards = points_outwards(edge, forward);
        let at_distance = |d: f64| point_at_distance(&outwards, jp, d);
        let (near, far) = (at_distance(SPLIT_NEAR * w), at_distance(SPLIT_FAR * w));
        if dist(near, far) < MIN_SPLIT_LINE_PX.max(w) {
            return None;
        }
        Some((w, ArmLine { near, far }))
    }

    /// Split stars: three or more straight strokes crossing so near one point that their ink
    /// leaves no hole between the crossings (an asterisk, the centre of a character like 米), which
    /// thinning splits into a small tree of junctions. Skeleton junctions linked by edges at most
    /// [`STAR_LINK`] widths long form a group; a group of three or more whose links form a tree
    /// (a cycle among them goes round a hole: separate crossings) is one vertex when its arms,
    /// at most [`MAX_STAR_ARMS`], pair up as straight strokes through it (each pair's two arms
    /// at different junctions, the line through their far anchors within half a stroke width of
    /// both near anchors and on the ink, as [`Work::merge_split_crossings`] pairs them), and the
    /// point nearest to all those lines lies on the ink, within half a width of a link and of
    /// every stroke's line: a point all the strokes' ink covers, which is what leaves no hole.
    /// With an odd number of arms (five or seven), one arm is left unpaired: a stroke starting
    /// at the star (炔, 木), which thinning forks off where the inks part, a width or more down
    /// the stroke it leaves; the star is one vertex when that arm, followed straight back,
    /// meets the stroke holding another arm of its junction within [`TEES_APART`] of the widest
    /// arms' widths of the star ([`starts_at`]), as the truth joins junctions closer than the
    /// widest stroke (docs/quality.md, "Session of 2026-12-06, third: crossings (issue 31)").
    pub(super) fn merge_split_stars(&mut self) {
        let mut degree = self.degrees();
        let mut at = self.incidence();
        let n = self.vertices.len();
        let mut sets = UnionFind::<usize>::new(n);
        let mut links = Vec::new();
        for (e, edge) in self.edges.iter().enumerate() {
            let Some(edge) = edge else { continue };
            let (a, b) = (edge.from, edge.to);
            if a == b || degree[a] < 3 || degree[b] < 3 {
                continue;
            }
            if edge.length() <= STAR_LINK * median(&edge.widths) {
                sets.union(a, b);
                links.push((e, a));
            }
        }
        // Each group's junctions and its links, by the group's root.
        let mut groups = vec![Vec::new(); n];
        for v in 0..n {
            if self.alive[v] && degree[v] >= 3 {
                groups[sets.find(v)].push(v);
            }
        }
        let mut internal_of = vec![Vec::new(); n];
        for (e, a) in links {
            internal_of[sets.find(a)].push(e);
        }
        for (group, internal) in groups.into_iter().zip(internal_of) {
            // One junction alone, or a cycle among them (a hole): no star.
            if group.len() < 2 || internal.len() + 1 != group.len() {
                continue;
            }
            let Some(c) = self.split_star(&group, &internal, &at) else {
                continue;
            };
            let Some(reach) = self.arm_reach(&c, &group, &internal, &at) else {
                continue;
            };
            self.merge_into_hub(&c, &group, &internal, reach, &mut at, &mut degree);
            degree[group[0]] = c.degree;
        }
    }

    /// The star of the junctions `group` linked by `internal` (see
    /// [`Work::merge_split_stars`]), or `None`.
    fn split_star(&self, group: &[usize], internal: &[usize], at: &[Vec<usize>]) -> Option<Vertex> {
        // Every arm leaving the group: its junction, width and line.
        let mut arms = Vec::new();
        for &j in group {
            for &e in at[j].iter().filter(|e| !internal.contains(e)) {
                let edge = self.edges[e].as_ref()?;
                if group.contains(&edge.from) && group.contains(&edge.to) {
                    // A longer edge back into the group: a loop, not a star's arm.
                    return None;
                }
                let (w, line) = self.arm_line(j, edge, edge.from == j)?;
                arms.push((j, w, line));
            }
        }
        // An odd star: a stroke starting at a crossing (炔, 木), one arm left unpaired.
        let odd = arms.len() % 2 != 0;
        if arms.len() < 5 || arms.len() > MAX_STAR_ARMS {
            return None;
        }
        let stroke = arms.iter().map(|a| a.1).fold(f64::INFINITY, f64::min);
        let tolerance = disk_radius(stroke);
        // How far a pair's line misses its near anchors (`None`: not one straight stroke).
        let mut miss_of = vec![vec![None; arms.len()]; arms.len()];
        for i in 0..arms.len() {
            for j in i + 1..arms.len() {
                miss_of[i][j] = self.stroke_miss(&arms[i].2, &arms[j].2, stroke);
            }
        }
        let pairs = best_pairing(&miss_of, odd)?;
        let lines = pairs
            .iter()
            .map(|&(i, j)| stroke_line(&arms[i].2, &arms[j].2))
            .collect::<Option<Vec<_>>>()?;
        let hub = line_intersection(&lines, 0.0)?;
        if odd {
            // The stroke the lone arm forks off: the one holding another arm of its junction.
            let lone = (0..arms.len()).find(|&k| pairs.iter().all(|&(i, j)| i != k && j != k))?;
            let stem = pairs.iter().position(|&(i, j)| {
                (i != lone && arms[i].0 == arms[lone].0) || (j != lone && arms[j].0 == arms[lone].0)
            })?;
            let widest = arms.iter().map(|a| a.1).fold(0.0f64, f64::max);
            if !starts_at(&arms[lone].2, lines[stem], hub, TEES_APART * widest) {
                return None;
            }
        }
        // The hub lies among the junctions: none farther from it than the longest link.
        let longest = internal
            .iter()
            .filter_map(|&e| self.edges[e].as_ref())
            .map(Edge::length)
            .fold(0.0f64, f64::max);
        let among = group
            .iter()
            .all(|&j| dist(self.vertices[j].pos, hub) <= longest + tolerance);
        let covered = lines
            .iter()
            .all(|&(p, d)| line_dist(hub, p, [p[0] + d[0], p[1] + d[1]]) <= tolerance);
        if !among || !covered || !self.ink.at(hub) {
            return None;
        }
        Some(Vertex {
            pos: hub,
            degree: arms.len(),
            width: stroke,
        })
    }
}

/// A split star's junctions are linked by edges at most this many widths long: three strokes
/// whose ink leaves no hole between their crossings cross at most `sqrt(3)` widths apart.
const STAR_LINK: f64 = 2.0;

/// The most arms a split star is looked for with (every pairing of 8 arms: 105; of 7 with one
/// left unpaired: 105).
const MAX_STAR_ARMS: usize = 8;

/// The pairing of all arms (`miss[i][j]` for `i < j`: how far the pair misses a straight
/// stroke, `None` when it is none) with the least summed miss, with one arm left unpaired when
/// `lone`; `None` when there is none.
fn best_pairing(miss: &[Vec<Option<f64>>], lone: bool) -> Option<Vec<(usize, usize)>> {
    fn search(
        miss: &[Vec<Option<f64>>],
        used: &mut [bool],
        pairs: &mut Vec<(usize, usize)>,
        (sum, lone): (f64, bool),
        best: &mut Option<(f64, Vec<(usize, usize)>)>,
    ) {
        let Some(i) = used.iter().position(|&u| !u) else {
            if !lone && best.as_ref().is_none_or(|(s, _)| sum < *s) {
                *best = Some((sum, pairs.clone()));
            }
            return;
        };
        used[i] = true;
        if lone {
            search(miss, used, pairs, (sum, false), best);
        }
        for j in i + 1..used.len() {
            if used[j] {
                continue;
            }
            let Some(m) = miss[i][j] else { continue };
            used[j] = true;
            pairs.push((i, j));
            search(miss, used, pairs, (sum + m, lone), best);
            pairs.pop();
            used[j] = false;
        }
        used[i] = false;
    }
    let mut best = None;
    search(
        miss,
        &mut vec![false; miss.len()],
        &mut Vec::new(),
        (0.0, lone),
        &mut best,
    );
    best.map(|(_, pairs)| pairs)
}

/// Whether the stroke of the arm `arm`, followed straight back from its stretch, starts at the
/// star `hub` on the stroke `stem` it forks off: it leaves that stroke's line at more than
/// [`MIN_TEE_SINE`] and meets it within `apart` px of the hub (the truth joins junctions closer
/// than the widest stroke at them, as [`Work::stems_apart`] measures), pointing away from the
/// hub.
fn starts_at(arm: &ArmLine, stem: ([f64; 2], [f64; 2]), hub: [f64; 2], apart: f64) -> bool {
    let Some(u) = unit([arm.near[0] - arm.far[0], arm.near[1] - arm.far[1]]) else {
        return false;
    };
    let d = stem.1;
    if dist(arm.far, hub) <= dist(arm.near, hub)
        || (u[0] * d[1] - u[1] * d[0]).abs() <= MIN_TEE_SINE
    {
        return false;
    }
    line_intersection(&[stem, (arm.far, u)], 0.0).is_some_and(|m| dist(m, hub) < apart)
}

/// Whether the arms `p` and `q` (their far-to-near stretches and the chord between their near
/// anchors) bend as one curve of constant curvature: the curvature from `p`'s stretch to the
/// chord and from the chord to `q`'s (turn over the distance between the pieces' middles)
/// differ by less than a curve `tolerance` px off the other over the span of the far anchors
/// shows (`8 tolerance / span^2`, the sagitta's) plus what a pixel across each piece makes
/// ([`PIXEL_PX`]). An S, two arms offset either side of one line
/// (the forks of a '>-<' bar, two T's), turns one way and back.
fn one_bend(p: &ArmLine, q: &ArmLine, tolerance: f64) -> bool {
    let pieces = [(p.far, p.near), (p.near, q.near), (q.near, q.far)];
    // The turn from piece `a` to piece `b` over the distance between their middles, and how
    // much of that the pixel grid alone can make (a pixel across each piece's length).
    let turn = |a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])| {
        let (u, v) = (
            [a.1[0] - a.0[0], a.1[1] - a.0[1]],
            [b.1[0] - b.0[0], b.1[1] - b.0[1]],
        );
        let (la, lb) = (dist(a.0, a.1), dist(b.0, b.1));
        let angle = (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1]);
        let apart = (la + lb) / 2.0;
        (la > 0.0 && lb > 0.0).then(|| (angle / apart, (PIXEL_PX / la + PIXEL_PX / lb) / apart))
    };
    let (Some((k1, n1)), Some((k2, n2))) = (turn(pieces[0], pieces[1]), turn(pieces[1], pieces[2]))
    else {
        return false;
    };
    let span = dist(p.far, q.far);
    span > 0.0 && (k1 - k2).abs() <= 8.0 * tolerance / (span * span) + n1 + n2
}

/// The line of the stroke whose two arms are `p` and `q`, through their far anchors (a point and
/// a unit direction); `None` when the anchors coincide.
fn stroke_line(p: &ArmLine, q: &ArmLine) -> Option<([f64; 2], [f64; 2])> {
    unit([q.far[0] - p.far[0], q.far[1] - p.far[1]]).map(|d| (p.far, d))
}

/// The distance from `p` to the line through `a` and `b` (infinite when they coincide).
fn line_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let n = hypot(d[0], d[1]);
    if n == 0.0 {
        return f64::INFINITY;
    }
    ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]).abs() / n
}

/// What one more part (a vertex and an edge) costs when the ink decides between one crossing
/// and two junctions: half a square of the stroke's width, as a spur decided by the ink
/// (docs/quality.md, "Deciding spurs by the ink").
const INK_PART_COST: f64 = 0.5;

/// Polylines are drawn with the round pen as disks at most this far apart (px).
const PEN_STEP_PX: f64 = 0.5;

/// One arm of a link's junction as the ink test draws it ([`Work::ink_crossing`]): the arm's
/// points from the junction out to its near anchor (what only the two-junction drawing has),
/// from the near anchor to the far one (what both drawings share), its median width and
/// anchors.
struct InkArm {
    inner: Vec<[f64; 2]>,
    outer: Vec<[f64; 2]>,
    width: f64,
    line: ArmLine,
}

/// The points of `path` resampled at most [`PEN_STEP_PX`] apart.
fn densify(path: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for s in path.windows(2) {
        let n = (dist(s[0], s[1]) / PEN_STEP_PX).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push([
                s[0][0] + t * (s[1][0] - s[0][0]),
                s[0][1] + t * (s[1][1] - s[0][1]),
            ]);
        }
    }
    if let Some(&last) = path.last() {
        out.push(last);
    }
    out
}

/// The cubic Hermite curve from `p0` leaving along the unit `t0` to `p1` arriving along the unit
/// `t1`, tangents as long as the chord: the smoothest way one stroke goes on through a crossing
/// from one arm to the other, sampled at most [`PEN_STEP_PX`] apart.
fn hermite(p0: [f64; 2], t0: [f64; 2], p1: [f64; 2], t1: [f64; 2]) -> Vec<[f64; 2]> {
    let l = dist(p0, p1);
    let n = (1.5 * l / PEN_STEP_PX).ceil().max(1.0) as usize;
    (0..=n)
        .map(|k| {
            let s = k as f64 / n as f64;
            let (s2, s3) = (s * s, s * s * s);
            let (h00, h10, h01, h11) = (
                2.0 * s3 - 3.0 * s2 + 1.0,
                s3 - 2.0 * s2 + s,
                -2.0 * s3 + 3.0 * s2,
                s3 - s2,
            );
            [0, 1].map(|i| h00 * p0[i] + h10 * l * t0[i] + h01 * p1[i] + h11 * l * t1[i])
        })
        .collect()
}

/// Where the polylines `p` and `q` cross, the crossing nearest `near`; `None` when they do not.
fn polyline_crossing(p: &[[f64; 2]], q: &[[f64; 2]], near: [f64; 2]) -> Option<[f64; 2]> {
    let mut best: Option<[f64; 2]> = None;
    for a in p.windows(2) {
        for b in q.windows(2) {
            let r = [a[1][0] - a[0][0], a[1][1] - a[0][1]];
            let s = [b[1][0] - b[0][0], b[1][1] - b[0][1]];
            let denom = r[0] * s[1] - r[1] * s[0];
            if denom.abs() < 1e-12 {
                continue;
            }
            let d = [b[0][0] - a[0][0], b[0][1] - a[0][1]];
            let t = (d[0] * s[1] - d[1] * s[0]) / denom;
            let u = (d[0] * r[1] - d[1] * r[0]) / denom;
            if !(0.0..=1.0).contains(&t) || !(0.0..=1.0).contains(&u) {
                continue;
            }
            let x = [a[0][0] + t * r[0], a[0][1] + t * r[1]];
            if best.is_none_or(|b| dist(x, near) < dist(b, near)) {
                best = Some(x);
            }
        }
    }
    best
}

/// The point of `edge` `d` from its junction at `jp` ([`point_at_distance`]), the edge read
/// from its start when `forward`.
pub(super) fn arm_point(edge: &Edge, forward: bool, jp: [f64; 2], d: f64) -> [f64; 2] {
    point_at_distance(&points_outwards(edge, forward), jp, d)
}

/// The first point of an arm (`outwards`, listed from the junction at `jp`) `d` from the
/// junction, on the segment that reaches that far (an arm an earlier merge joined straight to
/// its junction has long segments); the arm's last point when none does.
fn point_at_distance(outwards: &[[f64; 2]], jp: [f64; 2], d: f64) -> [f64; 2] {
    let Some(k) = outwards
        .iter()
        .position(|&p| cmp_dist(p, jp, d).is_some_and(Ordering::is_ge))
    else {
        return outwards[outwards.len() - 1];
    };
    if k == 0 {
        return outwards[0];
    }
    let (a, b) = (outwards[k - 1], outwards[k]);
    let (da, db) = (dist(a, jp), dist(b, jp));
    let t = if db > da { (d - da) / (db - da) } else { 1.0 };
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

impl Work {
    /// The arms at the degree-3 junction `j` other than `link` as the ink test draws them;
    /// `None` when there are not two or one is too short for a line.
    fn ink_arms(&self, j: usize, link: usize, at: &[Vec<usize>]) -> Option<Vec<InkArm>> {
        let jp = self.vertices[j].pos;
        let mut arms = Vec::new();
        for (edge, forward) in self.other_arms(j, link, at)? {
            let (width, outwards, line) = self.stretch(j, edge, forward, SPLIT_NEAR, SPLIT_FAR)?;
            let (d_near, d_far) = (dist(line.near, jp), dist(line.far, jp));
            let mut inner: Vec<[f64; 2]> = outwards
                .iter()
                .copied()
                .take_while(|&p| dist(p, jp) < d_near)
                .collect();
            inner.push(line.near);
            let mut outer = vec![line.near];
            outer.extend(
                outwards
                    .iter()
                    .copied()
                    .skip_while(|&p| dist(p, jp) < d_near)
                    .take_while(|&p| dist(p, jp) < d_far),
            );
            outer.push(line.far);
            arms.push(InkArm {
                inner,
                outer,
                width,
                line,
            });
        }
        (arms.len() >= 2).then_some(arms)
    }

    /// The ink's choice between one crossing and two junctions for the degree-3 junctions `a`
    /// and `b` joined by `link`: two drawings with a round pen of the strokes' measured widths,
    /// "one X" (each arm at `a` going on smoothly, [`hermite`], into one at `b` from near anchor
    /// to near anchor, the two strokes crossing) and "two Y's joined by a bar" (the skeleton's
    /// own arms into their junctions and the link, drawn no wider than the widest arm: a bar is
    /// a stroke of the same pen), each with the arms' stretches from near to far anchor they
    /// share. Each costs the ink pixels it leaves uncovered plus the background pixels it
    /// covers; the pixels both or neither cover cost both the same. A pairing whose strokes
    /// draw over more of a hole of the ink (`holes`) than the two Y's do is none: every hole is
    /// a cycle's, and a stroke across one is not on the ink (the cells of a grid, where two T's
    /// on the frame and the cell between them could pass for a blob). The crossing of the
    /// better pairing and by how many pixels "one X" costs less (`None` when neither pairing's
    /// strokes cross).
    fn ink_crossing(
        &self,
        link: usize,
        a: usize,
        b: usize,
        at: &[Vec<usize>],
        holes: &OnceCell<Holes>,
    ) -> Option<(Vertex, f64)> {
        let arms_a = self.ink_arms(a, link, at)?;
        let arms_b = self.ink_arms(b, link, at)?;
        let link_edge = self.edges[link].as_ref()?;
        let widest = arms_a
            .iter()
            .chain(&arms_b)
            .map(|arm| arm.width)
            .fold(0.0f64, f64::max);
        let stroke = arms_a
            .iter()
            .chain(&arms_b)
            .map(|arm| arm.width)
            .fold(f64::INFINITY, f64::min);
        let bar = median(&link_edge.widths).min(widest);
        let middle = link_edge.points[link_edge.points.len() / 2];
        // The pens each drawing has alone, and those both have.
        let pens = |path: &[[f64; 2]], w: f64| -> Vec<([f64; 2], f64)> {
            densify(path).into_iter().map(|p| (p, w)).collect()
        };
        let mut shared = Vec::new();
        let mut two = pens(&link_edge.points, bar);
        for arm in arms_a.iter().chain(&arms_b) {
            shared.extend(pens(&arm.outer, arm.width));
            two.extend(pens(&arm.inner, arm.width));
        }
        let pairs = [[(0, 0), (1, 1)], [(0, 1), (1, 0)]];
        let mut best: Option<(Vertex, f64)> = None;
        for pair in pairs {
            let strokes: Vec<(Vec<[f64; 2]>, f64, f64)> = pair
                .iter()
                .map(|&(i, j)| {
                    let (p, q) = (&arms_a[i], &arms_b[j]);
                    let t0 = unit([
                        p.line.near[0] - p.line.far[0],
                        p.line.near[1] - p.line.far[1],
                    ])?;
                    let t1 = unit([
                        q.line.far[0] - q.line.near[0],
                        q.line.far[1] - q.line.near[1],
                    ])?;
                    Some((hermite(p.line.near, t0, q.line.near, t1), p.width, q.width))
                })
                .collect::<Option<_>>()?;
            let Some(hub) = polyline_crossing(&strokes[0].0, &strokes[1].0, middle) else {
                continue;
            };
            if !self.ink.at(hub) {
                continue;
            }
            let mut one = Vec::new();
            for (path, w0, w1) in &strokes {
                let n = path.len().max(2) - 1;
                one.extend(
                    path.iter()
                        .enumerate()
                        .map(|(k, &p)| (p, w0 + (w1 - w0) * k as f64 / n as f64)),
                );
            }
            let (gain, over_holes) = self.ink_gain(&one, &two, &shared, holes);
            if over_holes > 0.0 {
                continue;
            }
            if best.as_ref().is_none_or(|(_, g)| gain > *g) {
                best = Some((
                    Vertex {
                        pos: hub,
                        degree: 4,
                        width: stroke,
                    },
                    gain,
                ));
            }
        }
        best
    }

    /// The crossing of the degree-3 junctions `a` and `b` joined by `link` when the ink prefers
    /// one X ([`Work::ink_crossing`]) by more than one part's cost ([`INK_PART_COST`] squared
    /// widths: "two Y's joined by a bar" has one vertex and one edge more) and the link is at
    /// most [`CURVED_LINK`] widths long (docs/quality.md, "Deciding crossings by the ink").
    fn ink_decides_crossing(
        &self,
        link: usize,
        a: usize,
        b: usize,
        at: &[Vec<usize>],
        holes: &OnceCell<Holes>,
    ) -> Option<Vertex> {
        let length = self.edges[link].as_ref()?.length();
        let stroke = [a, b]
            .iter()
            .filter_map(|&j| self.ink_arms(j, link, at))
            .flatten()
            .map(|arm| arm.width)
            .fold(f64::INFINITY, f64::min);
        if length > CURVED_LINK * stroke {
            return None;
        }
        let (c, gain) = self.ink_crossing(link, a, b, at, holes)?;
        let w = c.width;
        (gain > INK_PART_COST * w * w).then_some(c)
    }

    /// How many pixels the drawing `one` costs less than `two` (each a list of round pens: a
    /// point and a full width), the pixels `shared` covers left out: over the pixels one of them
    /// covers and the other not, an ink pixel counts for the drawing covering it and a
    /// background pixel against it.
    fn ink_gain(
        &self,
        one: &[([f64; 2], f64)],
        two: &[([f64; 2], f64)],
        shared: &[([f64; 2], f64)],
        holes: &OnceCell<Holes>,
    ) -> (f64, f64) {
        let all = || one.iter().chain(two).chain(shared);
        let mut min = [f64::INFINITY; 2];
        let mut max = [f64::NEG_INFINITY; 2];
        for &(p, w) in all() {
            let r = disk_radius(w);
            for k in 0..2 {
                min[k] = min[k].min(p[k] - r);
                max[k] = max[k].max(p[k] + r);
            }
        }
        if !min[0].is_finite() {
            return (0.0, 0.0);
        }
        let x0 = min[0].floor() as i64;
        let y0 = min[1].floor() as i64;
        let (nx, ny) = (
            (max[0].ceil() as i64 - x0 + 1) as usize,
            (max[1].ceil() as i64 - y0 + 1) as usize,
        );
        let mut flags = vec![0u8; nx * ny];
        for (bit, list) in [(1u8, one), (2, two), (4, shared)] {
            for &(p, w) in list {
                let r = disk_radius(w);
                for y in ((p[1] - r - 0.5).floor() as i64)..=((p[1] + r - 0.5).ceil() as i64) {
                    for x in ((p[0] - r - 0.5).floor() as i64)..=((p[0] + r - 0.5).ceil() as i64) {
                        let c = [x as f64 + 0.5, y as f64 + 0.5];
                        if cmp_dist(c, p, r).is_some_and(Ordering::is_ge) {
                            continue;
                        }
                        let (ix, iy) = (x - x0, y - y0);
                        if ix >= 0 && iy >= 0 && (ix as usize) < nx && (iy as usize) < ny {
                            flags[iy as usize * nx + ix as usize] |= bit;
                        }
                    }
                }
            }
        }
        let mut gain = 0.0;
        let mut over_holes = 0.0;
        for (i, &f) in flags.iter().enumerate() {
            let sign = match f {
                1 => 1.0,
                2 => -1.0,
                _ => continue,
            };
            let c = [
                (x0 + (i % nx) as i64) as f64 + 0.5,
                (y0 + (i / nx) as i64) as f64 + 0.5,
            ];
            gain += sign * if self.ink.at(c) { 1.0 } else { -1.0 };
            if self.in_hole(holes, c) {
                over_holes += sign;
            }
        }
        (gain, over_holes)
    }

    /// Whether the pixel centre `c` is background enclosed by the ink (`holes`, found by
    /// [`Holes::new`] the first time a pixel is asked).
    fn in_hole(&self, holes: &OnceCell<Holes>, c: [f64; 2]) -> bool {
        let (x, y) = (
            (c[0] - self.ink.origin[0]).floor(),
            (c[1] - self.ink.origin[1]).floor(),
        );
        x >= 0.0
            && y >= 0.0
            && (x as usize) < self.ink.width
            && (y as usize) < self.ink.height
            && holes
                .get_or_init(|| Holes::new(&self.ink))
                .at(x as usize, y as usize)
    }
}

/// The holes of an ink window: its background pixels that no 4-connected path of background
/// joins to the window's border. Kept as the rows' runs of background, joined by a union-find
/// where runs of neighbouring rows share a column, so that finding them costs the runs, not a
/// flood fill over every background pixel of the window (docs/performance.md, "Session of
/// 2026-12-06: pages").
struct Holes {
    /// Where each row's runs start in `runs`: row `y`'s are `runs[rows[y]..rows[y + 1]]`.
    rows: Vec<usize>,
    /// The runs of background, each its first column and one past its last, row by row from
    /// left to right.
    runs: Vec<(usize, usize)>,
    /// Whether each run lies in a hole.
    hole: Vec<bool>,
}

impl Holes {
    fn new(ink: &Ink) -> Holes {
        let (w, h) = (ink.width, ink.height);
        let mut rows = Vec::with_capacity(h + 1);
        let mut runs = Vec::new();
        for y in 0..h {
            rows.push(runs.len());
            let row = &ink.mask[y * w..(y + 1) * w];
            let mut x = 0;
            while let Some(start) = next_with(row, x, false) {
                let end = next_with(row, start, true).unwrap_or(w);
                runs.push((start, end));
                x = end;
            }
        }
        rows.push(runs.len());
        let mut sets = UnionFind::<usize>::new(runs.len());
        for y in 1..h {
            // Runs of rows y - 1 and y that share a column are 4-connected.
            let (mut i, mut j) = (rows[y - 1], rows[y]);
            while i < rows[y] && j < rows[y + 1] {
                let (above, below) = (runs[i], runs[j]);
                if above.0 < below.1 && below.0 < above.1 {
                    sets.union(i, j);
                }
                if above.1 < below.1 {
                    i += 1;
                } else {
                    j += 1;
                }
            }
        }
        let mut outside = vec![false; runs.len()];
        for (y, row) in rows.windows(2).enumerate() {
            for r in row[0]..row[1] {
                let (start, end) = runs[r];
                if y == 0 || y + 1 == h || start == 0 || end == w {
                    outside[sets.find_mut(r)] = true;
                }
            }
        }
        let hole = (0..runs.len())
            .map(|r| !outside[sets.find_mut(r)])
            .collect();
        Holes { rows, runs, hole }
    }

    /// Whether the pixel (`x`, `y`) of the window lies in a hole.
    fn at(&self, x: usize, y: usize) -> bool {
        let row = &self.runs[self.rows[y]..self.rows[y + 1]];
        // The last run starting at or before x, if x is in it.
        let k = row.partition_point(|&(start, _)| start <= x);
        k > 0 && x < row[k - 1].1 && self.hole[self.rows[y] + k - 1]
    }
}

/// The first column from `from` on whose pixel is `ink` (true: ink), if any. Eight pixels at a
/// time: a `bool` is a byte 0 or 1, so eight read as one `u64` hold a byte 1 at each ink pixel,
/// and the lowest byte that is what is looked for is the first such pixel.
fn next_with(row: &[bool], from: usize, ink: bool) -> Option<usize> {
    const ONES: u64 = 0x0101_0101_0101_0101;
    let rest = &row[from..];
    let mut eights = rest.chunks_exact(8);
    for (k, eight) in (&mut eights).enumerate() {
        let word = super::eight_pixels(eight);
        // A byte 1 at each pixel that is what is looked for.
        let found = if ink { word } else { !word & ONES };
        if found != 0 {
            return Some(from + 8 * k + found.trailing_zeros() as usize / 8);
        }
    }
    let done = rest.len() - eights.remainder().len();
    eights
        .remainder()
        .iter()
        .position(|&b| b == ink)
        .map(|i| from + done + i)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The holes by a flood fill of the background from the window's border (the
    /// straightforward version [`Holes`] replaces).
    fn flood_holes(ink: &Ink) -> Vec<bool> {
        let (w, h) = (ink.width, ink.height);
        let mut outside = vec![false; w * h];
        let mut stack: Vec<usize> = (0..w * h)
            .filter(|&i| {
                let (x, y) = (i % w, i / w);
                (x == 0 || y == 0 || x + 1 == w || y + 1 == h) && !ink.mask[i]
            })
            .collect();
        for &i in &stack {
            outside[i] = true;
        }
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            let mut push = |j: usize| {
                if !ink.mask[j] && !outside[j] {
                    outside[j] = true;
                    stack.push(j);
                }
            };
            if x > 0 {
                push(i - 1);
            }
            if x + 1 < w {
                push(i + 1);
            }
            if y > 0 {
                push(i - w);
            }
            if y + 1 < h {
                push(i + w);
            }
        }
        (0..w * h).map(|i| !ink.mask[i] && !outside[i]).collect()
    }

    #[test]
    fn the_rungs_of_a_fine_ladder_are_not_crossings() {
        // Rails and rungs three pixels wide, the holes between the rungs a pixel wide: finer
        // than the method's disks, whose graph sees crossings where two rungs leave a rail
        // side by side. Merged, the two T's made an X whose arms ran across the holes. Each
        // rung is two T's, each hole a cycle, and every edge on the ink.
        let rail = ".....#################################.....";
        let rungs = "........###.###.###.###.###.###.###........";
        let mut rows = vec!["", "", "", "", rail];
        rows.push("....###################################....");
        rows.push(rail);
        rows.extend([rungs; 5]);
        rows.push(rail);
        rows.push("....###################################....");
        rows.extend([rail, "", "", "", ""]);
        let binary = crate::synth::drawn(&rows);
        let graph = crate::trace_binary(&binary, &crate::params::Params::default())
            .expect("trace")
            .graph;
        let degrees: Vec<usize> = graph
            .junctions()
            .map(|v| graph.vertices[v].degree)
            .collect();
        assert_eq!(degrees, vec![3; 14]);
        assert_eq!(graph.cycles(), 6);
        for edge in &graph.edges {
            for p in &edge.points {
                let (x, y) = (p[0].floor() as i64, p[1].floor() as i64);
                assert!(binary.get(x, y), "{p:?} off the ink");
            }
        }
    }

    #[test]
    fn holes_from_runs_equal_the_flood_fill() {
        let mut rng = crate::test_rng::XorShift::new(0x9e37_79b9_7f4a_7c15);
        let mut next = || rng.next_u64();
        let mut holes_seen = 0;
        for case in 0..400 {
            let (w, h) = (1 + (next() % 40) as usize, 1 + (next() % 40) as usize);
            // From sparse to dense ink: dense masks leave many small holes.
            let percent = 20 + case % 60;
            let mask: Vec<bool> = (0..w * h).map(|_| next() % 100 < percent).collect();
            let ink = Ink {
                mask,
                width: w,
                height: h,
                origin: [0.0, 0.0],
            };
            let expected = flood_holes(&ink);
            let holes = Holes::new(&ink);
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(
                        holes.at(x, y),
                        expected[y * w + x],
                        "case {case} at ({x}, {y})"
                    );
                }
            }
            holes_seen += expected.iter().filter(|&&b| b).count();
        }
        assert!(holes_seen > 1000, "the cases have holes: {holes_seen}");
    }

    #[test]
    fn the_next_pixel_eight_at_a_time_is_the_one_by_one_search() {
        let mut rng = crate::test_rng::XorShift::new(0x9e37_79b9_7f4a_7c15);
        let mut found = 0;
        for len in [0usize, 1, 7, 8, 9, 15, 16, 17, 63, 64, 65, 200] {
            for density in [0u64, 1, 8, 15, 16] {
                let row: Vec<bool> = (0..len).map(|_| rng.next_u64() % 16 < density).collect();
                for from in 0..=len {
                    for ink in [false, true] {
                        let one_by_one = row[from..].iter().position(|&b| b == ink);
                        let expected = one_by_one.map(|i| from + i);
                        assert_eq!(next_with(&row, from, ink), expected, "{row:?} {from} {ink}");
                        found += usize::from(expected.is_some());
                    }
                }
            }
        }
        assert!(found > 2_000, "{found}");
    }
}
