//! The graph thinning tools extract from a one-pixel skeleton: junction pixels clustered into one
//! vertex, ends, dots, the pixel paths between them as edges, junction-free cycles as loops.

use crate::geometry::{floor_i64, tangents};
use crate::stroke_graph::{Edge, StrokeGraph, Vertex};

use super::thin::{neighbourhood, RING};
use super::MIN_WIDTH_PX;

/// The graph of a one-pixel skeleton in a `width` x `height` window: skeleton pixels with more
/// than two skeleton neighbours are junction pixels, clustered 8-connected into one vertex each;
/// pixels with one neighbour are ends, with none dots; the pixel paths between them are edges;
/// skeleton cycles without a junction become loops. Coordinates are pixel centers in the image,
/// the window's corner at `origin` (a junction's vertex, the mean of its pixels, is taken in the
/// image's coordinates, so that a chunk's window and the whole page's give it to the bit);
/// widths are `2 half_width - 1` (the pixel itself not counted), `half_width` of a window pixel
/// (0 off the ink). `pixels` are the skeleton's pixels in raster order, `codes` their skeleton
/// neighbours (bit k for [`RING`]`[k]`, [`neighbour_code`]), and `number` numbers them below
/// `ids` (distinct numbers), so that what is kept per pixel is the size of the skeleton's
/// numbering, not of the window (a chunk's window holds many times its ink).
pub(super) fn pixel_graph(
    width: usize,
    height: usize,
    (pixels, codes): (&[usize], &[u8]),
    (ids, number): (usize, impl Fn(usize) -> usize),
    half_width: impl Fn(usize) -> f32,
    origin: [i64; 2],
) -> StrokeGraph {
    let (w, h) = (width as i64, height as i64);
    // Each skeleton pixel's neighbours as a byte by `number`; the passes below read the bits in
    // `RING`'s order, as the window was read before (the tests compare the two).
    let (mut code, mut count) = (vec![0u8; ids], vec![0u8; ids]);
    for (&i, &c) in pixels.iter().zip(codes) {
        code[number(i)] = c;
        count[number(i)] = c.count_ones() as u8;
    }
    let step: [i64; 8] = RING.map(|(dx, dy)| dy * w + dx);
    let neighbours = |i: usize| code_neighbours(code[number(i)], &step, i);
    let center = |i: usize| {
        [
            (i as i64 % w + origin[0]) as f64 + 0.5,
            (i as i64 / w + origin[1]) as f64 + 0.5,
        ]
    };
    let width_at = |p: [f64; 2]| {
        let (x, y) = (
            (floor_i64(p[0]) - origin[0]).clamp(0, w - 1),
            (floor_i64(p[1]) - origin[1]).clamp(0, h - 1),
        );
        (2.0 * f64::from(half_width((y * w + x) as usize)) - 1.0).max(MIN_WIDTH_PX)
    };
    // Neighbour counts (at most 8) and vertex ids, kept small and by `number`: the window can be a
    // whole page. Every pass below walks the skeleton's pixels, not the window.

    const NONE: u32 = u32::MAX;
    let mut vertex_of = vec![NONE; ids];
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut stack = Vec::new();
    for &i in pixels {
        if vertex_of[number(i)] != NONE || count[number(i)] == 2 {
            continue;
        }
        let id = vertices.len();
        let mut sum = [0.0, 0.0];
        let mut members = 0.0;
        if count[number(i)] > 2 {
            stack.push(i);
            vertex_of[number(i)] = id as u32;
            while let Some(j) = stack.pop() {
                let c = center(j);
                sum = [sum[0] + c[0], sum[1] + c[1]];
                members += 1.0;
                for k in neighbours(j) {
                    if count[number(k)] > 2 && vertex_of[number(k)] == NONE {
                        vertex_of[number(k)] = id as u32;
                        stack.push(k);
                    }
                }
            }
        } else {
            vertex_of[number(i)] = id as u32;
            sum = center(i);
            members = 1.0;
        }
        let pos = [sum[0] / members, sum[1] / members];
        vertices.push(Vertex {
            pos,
            degree: 0,
            width: width_at(pos),
        });
    }

    let mut edges: Vec<Edge> = Vec::new();
    let mut visited = vec![false; ids];
    // Each path is walked into one buffer and its edge given a copy of its own size: growing a
    // fresh vector pixel by pixel reallocated it several times per edge.
    let mut path: Vec<[f64; 2]> = Vec::new();
    let make_edge = |from: usize, to: usize, points: Vec<[f64; 2]>, edges: &mut Vec<Edge>| {
        let widths = points.iter().map(|&p| width_at(p)).collect();
        edges.push(Edge {
            from,
            to,
            points,
            widths,
            directions: Vec::new(),
        });
    };
    for &a in pixels.iter().filter(|&&i| vertex_of[number(i)] != NONE) {
        let from = vertex_of[number(a)] as usize;
        for u in neighbours(a) {
            if vertex_of[number(u)] != NONE {
                if vertex_of[number(u)] as usize != from && a < u {
                    let points = vec![
                        vertices[from].pos,
                        vertices[vertex_of[number(u)] as usize].pos,
                    ];
                    make_edge(from, vertex_of[number(u)] as usize, points, &mut edges);
                }
                continue;
            }
            if visited[number(u)] {
                continue;
            }
            path.clear();
            path.push(vertices[from].pos);
            let (mut prev, mut cur) = (a, u);
            let to = loop {
                visited[number(cur)] = true;
                path.push(center(cur));
                let next = neighbours(cur).find(|&k| k != prev);
                match next {
                    Some(k) if vertex_of[number(k)] != NONE => {
                        break Some(vertex_of[number(k)] as usize)
                    }
                    Some(k) if !visited[number(k)] => {
                        prev = cur;
                        cur = k;
                    }
                    _ => break None,
                }
            };
            let Some(to) = to else { continue };
            if to == from && path.len() <= 3 {
                continue;
            }
            path.push(vertices[to].pos);
            make_edge(from, to, path.clone(), &mut edges);
        }
    }
    for &s in pixels.iter().filter(|&&i| count[number(i)] == 2) {
        if visited[number(s)] {
            continue;
        }
        let id = vertices.len();
        vertices.push(Vertex {
            pos: center(s),
            degree: 0,
            width: width_at(center(s)),
        });
        path.clear();
        path.push(center(s));
        visited[number(s)] = true;
        let (mut prev, mut cur) = (s, neighbours(s).next().unwrap_or(s));
        while cur != s && !visited[number(cur)] {
            visited[number(cur)] = true;
            path.push(center(cur));
            match neighbours(cur).find(|&k| k != prev) {
                Some(k) => {
                    prev = cur;
                    cur = k;
                }
                None => break,
            }
        }
        path.push(center(s));
        make_edge(id, id, path.clone(), &mut edges);
    }
    for e in &edges {
        vertices[e.from].degree += 1;
        vertices[e.to].degree += 1;
    }
    let mut graph = StrokeGraph {
        width: width as u32,
        height: height as u32,
        vertices,
        edges,
    };
    set_directions(&mut graph);
    graph
}

/// The skeleton neighbours of window pixel `i` as a byte, bit k for [`RING`]`[k]`: away from
/// the window's border read as the three rows of the 3 x 3 block around it ([`neighbourhood`],
/// the thinning's), at the border one neighbour at a time, each tested against the window.
pub(super) fn neighbour_code(skeleton: &[bool], w: i64, h: i64, i: usize) -> u8 {
    let (x, y) = ((i as i64) % w, (i as i64) / w);
    if x > 0 && y > 0 && x + 1 < w && y + 1 < h {
        return neighbourhood(skeleton, w as usize, i);
    }
    let on = |x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && skeleton[(y * w + x) as usize];
    RING.iter()
        .enumerate()
        .filter(|&(_, &(dx, dy))| on(x + dx, y + dy))
        .fold(0u8, |code, (k, _)| code | 1 << k)
}

/// The window pixels of the neighbours in `code` (bit k for [`RING`]`[k]`, `step[k]` its offset
/// in the window) of window pixel `i`, in `RING`'s order.
fn code_neighbours(code: u8, step: &[i64; 8], i: usize) -> impl Iterator<Item = usize> + '_ {
    let mut bits = code;
    std::iter::from_fn(move || {
        (bits != 0).then(|| {
            let k = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            (i as i64 + step[k]) as usize
        })
    })
}

fn set_directions(graph: &mut StrokeGraph) {
    for edge in &mut graph.edges {
        edge.directions = tangents(&edge.points);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_neighbour_bytes_give_the_neighbours_read_from_the_window() {
        // Every pixel of random windows (one row or column up to 30 x 30, 5 % to full): the
        // neighbours decoded from its byte are those the window's ring gives, in the ring's
        // order (as each pass read them before the bytes).
        let mut lcg = crate::synth::lcg(2024u64);
        let mut next = move || (lcg() >> 33) as usize;
        let mut pixels = 0;
        for case in 0..300 {
            let (width, height) = match case % 10 {
                0 => (1, 1 + next() % 30),
                1 => (1 + next() % 30, 1),
                _ => (1 + next() % 30, 1 + next() % 30),
            };
            let percent = 5 + next() % 96;
            let skeleton: Vec<bool> = (0..width * height)
                .map(|_| next() % 100 < percent)
                .collect();
            let (w, h) = (width as i64, height as i64);
            let step: [i64; 8] = RING.map(|(dx, dy)| dy * w + dx);
            for i in (0..width * height).filter(|&i| skeleton[i]) {
                let (x, y) = ((i as i64) % w, (i as i64) / w);
                let read: Vec<usize> = RING
                    .iter()
                    .filter(|&&(dx, dy)| {
                        let (a, b) = (x + dx, y + dy);
                        a >= 0 && b >= 0 && a < w && b < h && skeleton[(b * w + a) as usize]
                    })
                    .map(|&(dx, dy)| ((y + dy) * w + x + dx) as usize)
                    .collect();
                let code = neighbour_code(&skeleton, w, h, i);
                assert_eq!(code.count_ones() as usize, read.len());
                let decoded: Vec<usize> = code_neighbours(code, &step, i).collect();
                assert_eq!(decoded, read, "{width} x {height}, pixel {i}");
                pixels += 1;
            }
        }
        assert!(pixels > 20_000, "{pixels}");
    }
}
