//! The fit on rendered strokes with known centerlines. The points are built here by brute force
//! (the raster stage is tested on its own) and the node graph is laid roughly along the truth with
//! deterministic jitter, as refinement would leave it.

use super::{fit_with_spacing, node_spacing};
use crate::binary::Binary;
use crate::draw::{render, Stroke};
use crate::geometry::segment_dist;
use crate::node_graph::{GraphNode, NodeGraph};
use crate::params::Params;
use crate::point_set::{Grid, PointSet};
use crate::stroke_graph::StrokeGraph;

/// The fit of one whole point set: its own node spacing.
fn fit(graph: &NodeGraph, points: &PointSet, params: &Params) -> StrokeGraph {
    fit_with_spacing(
        graph,
        points,
        params,
        node_spacing(&[graph], points, params),
    )
}

/// Points, 8-neighbours, half-widths (distance to the nearest background pixel center) and the
/// pixel grid of a mask.
fn point_set(binary: &Binary) -> PointSet {
    let (w, h) = (binary.width as i64, binary.height as i64);
    let mut set = PointSet {
        spacing: 1.0,
        ..PointSet::default()
    };
    let mut index = vec![Grid::NONE; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            if binary.get(x, y) {
                index[(y * w + x) as usize] = set.points.len() as u32;
                set.points.push([x as f64 + 0.5, y as f64 + 0.5]);
            }
        }
    }
    let grid = Grid {
        width: binary.width,
        height: binary.height,
        index,
        x0: 0,
        y0: 0,
    };
    let mut lists = Vec::with_capacity(set.points.len());
    for p in &set.points {
        let (x, y) = (p[0] as i64, p[1] as i64);
        let mut nearest = f64::INFINITY;
        for dy in -20..=20i64 {
            for dx in -20..=20i64 {
                if !binary.get(x + dx, y + dy) {
                    nearest = nearest.min(((dx * dx + dy * dy) as f64).sqrt());
                }
            }
        }
        set.half_width.push(nearest as f32);
        let mut list = Vec::new();
        for (dx, dy) in [
            (-1, -1),
            (0, -1),
            (1, -1),
            (-1, 0),
            (1, 0),
            (-1, 1),
            (0, 1),
            (1, 1),
        ] {
            if let Some(q) = grid.point_at(x + dx, y + dy) {
                list.push(q);
            }
        }
        lists.push(list);
    }
    set.set_neighbors_symmetric(&lists);
    set.grid = Some(grid);
    set.validate().unwrap();
    set
}

/// A deterministic jitter in [-amount, amount].
fn jitter(i: usize, amount: f64) -> [f64; 2] {
    let a = ((i * 7919 + 13) % 101) as f64 / 100.0 - 0.5;
    let b = ((i * 104_729 + 7) % 97) as f64 / 96.0 - 0.5;
    [2.0 * amount * a, 2.0 * amount * b]
}

/// Points every `step` along a polyline (both ends included), jittered.
fn along(line: &[[f64; 2]], step: f64, amount: f64, seed: usize) -> Vec<[f64; 2]> {
    let s = crate::geometry::arc_lengths(line);
    let length = s[s.len() - 1];
    let count = (length / step).round().max(1.0) as usize;
    (0..=count)
        .map(|j| {
            let (p, _) = crate::geometry::point_at(line, &s, length * j as f64 / count as f64);
            let d = jitter(seed + j, amount);
            [p[0] + d[0], p[1] + d[1]]
        })
        .collect()
}

/// A node graph on the given nodes and edges, each point owned by its nearest node.
fn node_graph(points: &PointSet, nodes: &[[f64; 2]], edges: &[[u32; 2]], width: f64) -> NodeGraph {
    let nodes: Vec<GraphNode> = nodes
        .iter()
        .map(|&pos| GraphNode {
            pos,
            r_min: width,
            width,
            direction: [1.0, 0.0],
            linear: true,
            cluster: None,
            tip: false,
        })
        .collect();
    let owner = points
        .points
        .iter()
        .map(|p| {
            (0..nodes.len())
                .min_by(|&a, &b| {
                    crate::geometry::dist(nodes[a].pos, *p)
                        .total_cmp(&crate::geometry::dist(nodes[b].pos, *p))
                })
                .unwrap() as u32
        })
        .collect();
    let mut edges: Vec<[u32; 2]> = edges.iter().map(|&[a, b]| [a.min(b), a.max(b)]).collect();
    edges.sort_unstable();
    let graph = NodeGraph {
        nodes,
        edges,
        owner,
    };
    graph.validate(points.len()).unwrap();
    graph
}

/// Edges joining consecutive nodes `from..to`.
fn path(from: u32, to: u32) -> Vec<[u32; 2]> {
    (from..to - 1).map(|i| [i, i + 1]).collect()
}

fn polyline_distance(p: [f64; 2], line: &[[f64; 2]]) -> f64 {
    line.windows(2)
        .map(|w| segment_dist(p, w[0], w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// Largest distance from the fitted centerlines (sampled every 0.5 px) to the truth.
fn worst_distance(graph: &StrokeGraph, truth: &[Vec<[f64; 2]>]) -> f64 {
    let mut worst: f64 = 0.0;
    for e in &graph.edges {
        for w in e.points.windows(2) {
            let steps = (crate::geometry::dist(w[0], w[1]) / 0.5).ceil().max(1.0) as usize;
            for j in 0..=steps {
                let t = j as f64 / steps as f64;
                let p = [
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ];
                let d = truth
                    .iter()
                    .map(|line| polyline_distance(p, line))
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
            }
        }
    }
    worst
}

fn fit_checked(graph: &NodeGraph, points: &PointSet, params: &Params) -> StrokeGraph {
    let result = fit(graph, points, params);
    result.validate().unwrap();
    result
}

/// Whether each true end has a degree-1 vertex within `tolerance`.
fn ends_found(graph: &StrokeGraph, ends: &[[f64; 2]], tolerance: f64) -> bool {
    ends.iter().all(|&t| {
        graph
            .endpoints()
            .any(|v| crate::geometry::dist(graph.vertices[v].pos, t) <= tolerance)
    })
}

fn arc(center: [f64; 2], radius: f64, from: f64, to: f64, count: usize) -> Vec<[f64; 2]> {
    (0..=count)
        .map(|i| {
            let a = from + (to - from) * i as f64 / count as f64;
            [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
        })
        .collect()
}

#[test]
fn straight_stroke_lies_on_its_centerline_and_reaches_its_ends() {
    let truth = vec![[10.3, 15.2], [85.7, 40.9]];
    let binary = render(&[Stroke::new(truth.clone(), 5.0)], 100, 60);
    let points = point_set(&binary);
    let nodes = along(&truth[..], 6.0, 0.7, 1);
    // Refinement leaves end nodes inside the cap, not at the true ends.
    let graph = node_graph(&points, &nodes, &path(0, nodes.len() as u32), 5.0);
    let result = fit_checked(&graph, &points, &Params::default());
    assert_eq!((result.vertices.len(), result.edges.len()), (2, 1));
    let worst = worst_distance(&result, std::slice::from_ref(&truth));
    assert!(worst <= 0.5, "{worst}");
    assert!(ends_found(&result, &truth, 1.0), "{:?}", result.vertices);
    // The widths follow the stroke (5 px, 2 x distance to the background at the center ~ 6).
    assert!(
        result.edges[0]
            .widths
            .iter()
            .all(|&w| (4.0..=7.0).contains(&w)),
        "{:?}",
        result.edges[0].widths
    );
    // The same points as a point list (no pixel grid): ink is "near a point".
    let mut list = points.clone();
    list.grid = None;
    let from_list = fit_checked(&graph, &list, &Params::default());
    let worst = worst_distance(&from_list, std::slice::from_ref(&truth));
    assert!(worst <= 0.5, "{worst}");
    assert!(
        ends_found(&from_list, &truth, 1.0),
        "{:?}",
        from_list.vertices
    );
    let d = result.edges[0].directions[3];
    let true_d = [75.4 / 79.66, 25.7 / 79.66];
    assert!((d[0] * true_d[0] + d[1] * true_d[1]).abs() > 0.99);
}

#[test]
fn curved_stroke_lies_on_its_centerline_and_reaches_its_ends() {
    let truth = arc([60.0, 55.0], 35.0, 0.2, 2.6, 200);
    let binary = render(&[Stroke::new(truth.clone(), 6.0)], 110, 100);
    let points = point_set(&binary);
    let nodes = along(&truth, 6.0, 0.8, 5);
    let graph = node_graph(&points, &nodes, &path(0, nodes.len() as u32), 6.0);
    let result = fit_checked(&graph, &points, &Params::default());
    assert_eq!(result.edges.len(), 1);
    let worst = worst_distance(&result, std::slice::from_ref(&truth));
    assert!(worst <= 0.5, "{worst}");
    assert!(
        ends_found(&result, &[truth[0], truth[200]], 1.0),
        "{:?}",
        result.vertices
    );
}

#[test]
fn t_junction_is_placed_where_the_stem_meets_the_bar() {
    let bar = vec![[10.0, 20.0], [90.0, 20.0]];
    let stem = vec![[50.0, 20.0], [50.0, 75.0]];
    let binary = render(
        &[
            Stroke::new(bar.clone(), 5.0),
            Stroke::new(stem.clone(), 5.0),
        ],
        100,
        90,
    );
    let points = point_set(&binary);
    // The junction node sits off the true junction, down the stem, as a merged cluster would.
    let left = along(&[[10.0, 20.0], [45.0, 20.0]], 6.0, 0.6, 1);
    let right = along(&[[55.0, 20.0], [90.0, 20.0]], 6.0, 0.6, 50);
    let down = along(&[[50.0, 26.0], [50.0, 75.0]], 6.0, 0.6, 100);
    let mut nodes = vec![[51.2, 22.1]];
    let (l0, r0) = (1u32, 1 + left.len() as u32);
    let d0 = r0 + right.len() as u32;
    nodes.extend(&left);
    nodes.extend(&right);
    nodes.extend(&down);
    let mut edges = path(l0, r0);
    edges.extend(path(r0, d0));
    edges.extend(path(d0, nodes.len() as u32));
    edges.extend([[0, r0 - 1], [0, r0], [0, d0]]);
    let graph = node_graph(&points, &nodes, &edges, 5.0);
    let result = fit_checked(&graph, &points, &Params::default());
    let junctions: Vec<usize> = result.junctions().collect();
    assert_eq!(junctions.len(), 1);
    let junction = result.vertices[junctions[0]].pos;
    assert!(
        crate::geometry::dist(junction, [50.0, 20.0]) <= 1.5,
        "{junction:?}"
    );
    assert!(
        ends_found(&result, &[[10.0, 20.0], [90.0, 20.0], [50.0, 75.0]], 1.0),
        "{:?}",
        result.vertices
    );
    let worst = worst_distance(&result, &[bar, stem]);
    assert!(worst <= 1.0, "{worst}");

    // The paper's own Eq. (4) runs on the same graph and keeps its topology.
    let paper = fit_checked(&graph, &points, &Params::paper());
    assert_eq!(paper.junctions().count(), 1);
    assert_eq!(paper.endpoints().count(), 3);
}

#[test]
fn a_circle_becomes_one_self_loop() {
    let truth = arc([50.0, 50.0], 25.0, 0.0, std::f64::consts::TAU, 400);
    let binary = render(&[Stroke::new(truth.clone(), 5.0)], 100, 100);
    let points = point_set(&binary);
    let mut nodes = along(&truth, 6.0, 0.7, 3);
    nodes.pop(); // the last node would repeat the first
    let count = nodes.len() as u32;
    let mut edges = path(0, count);
    edges.push([0, count - 1]);
    let graph = node_graph(&points, &nodes, &edges, 5.0);
    let result = fit_checked(&graph, &points, &Params::default());
    assert_eq!(result.vertices.len(), 1);
    assert_eq!(result.vertices[0].degree, 2);
    assert_eq!(result.edges.len(), 1);
    assert_eq!((result.edges[0].from, result.edges[0].to), (0, 0));
    assert_eq!(result.cycles(), 1);
    let worst = worst_distance(&result, &[truth]);
    assert!(worst <= 0.5, "{worst}");
}

#[test]
fn a_lone_blob_becomes_an_isolated_vertex() {
    let binary = render(
        &[Stroke::new(vec![[20.0, 20.0], [20.0, 20.0]], 10.0)],
        40,
        40,
    );
    let points = point_set(&binary);
    let graph = node_graph(&points, &[[21.0, 19.2]], &[], 10.0);
    let result = fit_checked(&graph, &points, &Params::default());
    assert_eq!(result.vertices.len(), 1);
    assert!(result.edges.is_empty());
    assert_eq!(result.vertices[0].degree, 0);
    assert!(
        crate::geometry::dist(result.vertices[0].pos, [20.0, 20.0]) < 0.5,
        "{:?}",
        result.vertices[0]
    );
    assert!(result.vertices[0].width >= 8.0);
}

#[test]
fn a_dot_refined_into_a_short_dash_is_one_vertex() {
    let mut binary = Binary::new(20, 20);
    for y in 8..12 {
        for x in 8..12 {
            binary.set(x, y, true);
        }
    }
    let points = point_set(&binary);
    let graph = node_graph(&points, &[[10.0, 9.6], [9.6, 10.4]], &[[0, 1]], 3.0);
    let result = fit_checked(&graph, &points, &Params::default());
    assert_eq!((result.vertices.len(), result.edges.len()), (1, 0));
    assert!(crate::geometry::dist(result.vertices[0].pos, [10.0, 10.0]) < 0.5);
    // Without clean-up the graph is taken as it is.
    let as_is = fit_checked(&graph, &points, &Params::paper());
    assert_eq!((as_is.vertices.len(), as_is.edges.len()), (2, 1));
}

#[test]
fn parallel_strokes_keep_their_own_points() {
    // Two strokes 3 px wide with a 2 px gap; the lower one's nodes are jittered toward the upper.
    let upper = vec![[10.0, 20.0], [70.0, 20.0]];
    let lower = vec![[10.0, 25.0], [70.0, 25.0]];
    let binary = render(
        &[
            Stroke::new(upper.clone(), 3.0),
            Stroke::new(lower.clone(), 3.0),
        ],
        80,
        40,
    );
    let points = point_set(&binary);
    let mut nodes = along(&upper, 4.0, 0.4, 1);
    let split = nodes.len() as u32;
    nodes.extend(along(&[[10.0, 24.0], [70.0, 24.0]], 4.0, 0.4, 9));
    let mut edges = path(0, split);
    edges.extend(path(split, nodes.len() as u32));
    let graph = node_graph(&points, &nodes, &edges, 3.0);
    let result = fit_checked(&graph, &points, &Params::default());
    assert_eq!(result.edges.len(), 2);
    for (edge, truth) in result.edges.iter().zip([&upper, &lower]) {
        for p in &edge.points {
            assert!(polyline_distance(*p, truth) <= 0.6, "{p:?} off {truth:?}");
        }
    }
}

#[test]
fn nothing_in_nothing_out() {
    let result = fit(
        &NodeGraph::default(),
        &PointSet::default(),
        &Params::default(),
    );
    assert!(result.vertices.is_empty() && result.edges.is_empty());
}

#[test]
fn a_site_over_a_neighbouring_stroke_takes_the_points_of_its_own() {
    // Two bars 2 px apart: separate components.
    let mut binary = Binary::new(32, 12);
    for x in 2..30 {
        for y in (2..5).chain(7..10) {
            binary.set(x, y, true);
        }
    }
    let points = point_set(&binary);
    let (components, sizes) = points.component_labels();
    assert_eq!(sizes.len(), 2);
    // One old node owns the upper bar; its site has drifted onto a pixel of the lower bar.
    let label: Vec<u32> = components.clone();
    let owned = super::assign::Groups::new(&label, 2);
    let site = [15.5, 7.5];
    assert!(points.grid.as_ref().unwrap().point_at(15, 7).is_some());
    let cells = super::assign::assign(
        &points,
        &components,
        &[Some(0)],
        &owned,
        &[site],
        &[[0, 0]],
        1.0,
    );
    assert_eq!(cells.of(0).len(), sizes[0], "the whole upper bar");
    assert!(cells.of(0).iter().all(|&p| components[p as usize] == 0));
}
