//! Arranging a fresh layout around what must not move: pinned nodes go exactly where the user
//! put them (`crate::pins`); nodes of the scene drawn before this one stay where they were (an
//! edit in the editor moves the drawing little); only new nodes are placed, beside their
//! neighbours as the fresh layout relates them, in free space. Routes between nodes that did
//! not move are kept; the others run straight from border to border.

use std::collections::HashMap;

use super::{detour, labels::around, Point, Rect, Scene, SceneEdge};
use crate::{
    geometry::{intersects, segment_meets_box},
    grid::Segments,
    layout::{parallel_edges, self_loop, Layout, Page},
    pins::{Pins, Rows},
};

/// What a scene is built from besides its graph.
#[derive(Debug, Clone, Copy, Default)]
pub struct Hints<'a> {
    /// Where the user put nodes (and the sizes they gave them).
    pub pins: Option<&'a Pins>,
    /// The scene of the same diagram drawn before: its nodes stay where they were, if it still
    /// holds at least half of this one's nodes.
    pub previous: Option<&'a Scene>,
    /// The page or screen the drawing is meant for: a fresh layout that does not fit it is
    /// reshaped towards its aspect ratio.
    pub page: Page,
    /// The rows of a fresh layout of the diagram before (the scene before's, or the sidecar's):
    /// the fresh layout keeps their order where it can.
    pub rows: Option<&'a Rows>,
}

/// A node to place: its id, its size, and the room its port symbols take left and right of it
/// (arranging keeps that room free too: its footprint).
pub(super) struct Node<'a> {
    pub id: &'a str,
    pub width: f64,
    pub height: f64,
    pub reach: (f64, f64),
    /// A nested component: its parent holds it (and moves it), arranging does not.
    pub held: bool,
}

impl Node<'_> {
    /// Its footprint's box, for its box `r`.
    fn footprint(&self, r: Rect) -> Rect {
        Rect { x: r.x - self.reach.0, width: r.width + self.reach.0 + self.reach.1, ..r }
    }
}

/// An edge to route: its id, its ends' ids and their indices.
pub(super) struct Edge<'a> {
    pub id: &'a str,
    pub source: &'a str,
    pub target: &'a str,
    pub from: usize,
    pub to: usize,
    /// The width of its widest end label (0 without): parallel edges run that far apart.
    pub end_label_width: f64,
}

/// Space kept between a placed node and the others.
const CLEARANCE: f64 = 20.0;
/// The step of the search for free space, and how far it looks before giving up on routes.
const STEP: f64 = 20.0;
const RINGS: usize = 60;
/// Right of and below the drawing.
const MARGIN: f64 = 20.0;

#[derive(Clone, Copy, PartialEq)]
enum Wanted {
    Pinned(Point),
    Kept(Rect),
    Free,
    /// Where its parent puts it.
    Held,
}

/// Moves `layout` (a fresh layout of `nodes` and `edges`) to honour `hints`; without pins and a
/// previous scene it stays as it is.
/// Nodes placed anew keep right of and below `corner` (the top left of the frame's body).
pub(super) fn arrange(layout: &mut Layout, nodes: &[Node], edges: &[Edge], hints: Hints, corner: Point) -> Arranged {
    let wanted = wanted(nodes, hints);
    if wanted.iter().all(|w| matches!(w, Wanted::Free | Wanted::Held)) {
        return Arranged::Fresh;
    }
    // Arranged as footprints (boxes with their ports' room), drawn as boxes.
    let footprints: Vec<Node> =
        nodes.iter().map(|n| Node { width: n.width + n.reach.0 + n.reach.1, reach: (0.0, 0.0), ..*n }).collect();
    let fresh: Vec<Point> =
        layout.positions.iter().zip(nodes).map(|(p, n)| Point { x: p.x - n.reach.0, ..*p }).collect();
    let (boxes, previous_routes) = place(&footprints, edges, &wanted, &fresh, hints.previous, corner);
    // Whether a node is not where the previous scene had it.
    let moved = |i: usize| !matches!(wanted[i], Wanted::Kept(was) if boxes[i] == was);
    let parallel = fan_positions(edges);
    // Indexed only when a route is drawn anew.
    let obstacles = std::cell::LazyCell::new(|| detour::Obstacles::new(&boxes));
    let mut labels: Vec<[Option<Rect>; 3]> = vec![[None; 3]; edges.len()];
    let mut rerouted = vec![false; edges.len()];
    for ((k, e), previous) in edges.iter().enumerate().zip(previous_routes) {
        // Kept unless a node that moved landed on it.
        let kept = previous.filter(|drawn| {
            !(0..boxes.len())
                .any(|i| moved(i) && drawn.route.windows(2).any(|s| segment_meets_box(s[0], s[1], boxes[i])))
        });
        rerouted[k] = kept.is_none();
        (layout.edges[k], labels[k]) = match kept {
            Some(drawn) => (drawn.route, drawn.labels),
            None => (anew(&obstacles, e, parallel[k]), [None; 3]),
        };
    }
    // A kept label stays unless a new route crosses it or a moved node covers it; the others
    // are placed afresh.
    let crossed = |r: Rect| {
        layout
            .edges
            .iter()
            .zip(&rerouted)
            .any(|(route, &new)| new && route.windows(2).any(|s| segment_meets_box(s[0], s[1], r)))
    };
    let covered = |r: Rect| (0..boxes.len()).any(|i| moved(i) && intersects(r, boxes[i]));
    let still = |label: Option<Rect>| label.filter(|&r| !crossed(r) && !covered(r)).map(|r| Point { x: r.x, y: r.y });
    layout.labels = labels.iter().map(|[middle, _, _]| still(*middle)).collect();
    layout.end_labels = labels.iter().map(|[_, tail, head]| [still(*tail), still(*head)]).collect();
    layout.positions = boxes.iter().zip(nodes).map(|(b, n)| Point { x: b.x + n.reach.0, y: b.y }).collect();
    let points = layout.edges.iter().flatten().map(|p| (p.x, p.y));
    let corners = boxes.iter().map(|b| (b.x + b.width, b.y + b.height));
    let (right, bottom) = points.chain(corners).fold((0.0f64, 0.0f64), |(w, h), (x, y)| (w.max(x), h.max(y)));
    layout.width = right + MARGIN;
    layout.height = bottom + MARGIN;
    Arranged::Around { kept: rerouted.iter().map(|r| !r).collect() }
}

/// What arranging did to the fresh layout.
pub(super) enum Arranged {
    /// Nothing: no node was pinned or drawn before; every route is the layout's.
    Fresh,
    /// Moved nodes: per edge, whether its route is the one drawn before (neither end moved).
    Around { kept: Vec<bool> },
}

/// Each node: pinned where its pin says, kept where the previous scene had it (if that scene
/// holds at least half of the nodes), or free.
fn wanted(nodes: &[Node], hints: Hints) -> Vec<Wanted> {
    let before: HashMap<&str, Rect> =
        hints.previous.map(|s| s.nodes.iter().map(|n| (n.id.as_str(), n.rect)).collect()).unwrap_or_default();
    let common = nodes.iter().filter(|n| before.contains_key(n.id)).count();
    let use_before = common > 0 && common * 2 >= nodes.len();
    nodes
        .iter()
        .map(|n| match (hints.pins.and_then(|p| p.get(n.id)), before.get(n.id)) {
            _ if n.held => Wanted::Held,
            (Some(pin), _) => Wanted::Pinned(Point { x: pin.x - n.reach.0, y: pin.y }),
            (None, Some(&was)) if use_before => Wanted::Kept(n.footprint(was)),
            _ => Wanted::Free,
        })
        .collect()
}

/// A route and its labels' boxes (middle, tail, head), as the previous scene drew them.
struct Drawn {
    route: Vec<Point>,
    labels: [Option<Rect>; 3],
}

/// Every node's box: pinned ones first, then kept ones (those of unchanged size first: a node
/// that grew is the one to make room), each where wanted if that is free, else at the nearest
/// free spot; then the free ones, beside their neighbours, clear of the routes and labels
/// that stay. With them, per edge, its previous route where both its ends are kept nodes placed
/// where they were (the free nodes placed last move none of those).
fn place(
    nodes: &[Node],
    edges: &[Edge],
    wanted: &[Wanted],
    fresh: &[Point],
    previous: Option<&Scene>,
    corner: Point,
) -> (Vec<Rect>, Vec<Option<Drawn>>) {
    let at = |i: usize, p: Point| Rect { x: p.x, y: p.y, width: nodes[i].width, height: nodes[i].height };
    let mut placed: Vec<Option<Rect>> = vec![None; nodes.len()];
    for (i, w) in wanted.iter().enumerate() {
        if let Wanted::Pinned(p) = *w {
            placed[i] = Some(at(i, p));
        }
    }
    let kept: Vec<(usize, Rect)> = wanted
        .iter()
        .enumerate()
        .filter_map(|(i, w)| if let Wanted::Kept(was) = *w { Some((i, was)) } else { None })
        .collect();
    let grown = |&(i, was): &(usize, Rect)| (was.width, was.height) != (nodes[i].width, nodes[i].height);
    for &(i, was) in kept.iter().filter(|k| !grown(k)).chain(kept.iter().filter(|k| grown(k))) {
        let obstacles = Obstacles { corner, ..Obstacles::default() };
        placed[i] = Some(free_spot(at(i, Point { x: was.x, y: was.y }), &placed, &obstacles));
    }
    let before: HashMap<&str, &SceneEdge> =
        previous.map(|s| s.edges.iter().map(|e| (e.id.as_str(), e)).collect()).unwrap_or_default();
    let unmoved = |i: usize| matches!(wanted[i], Wanted::Kept(was) if placed[i] == Some(was));
    let previous_routes: Vec<Option<Drawn>> = edges
        .iter()
        .map(|e| {
            let old = before.get(e.id).filter(|o| o.source == e.source && o.target == e.target)?;
            let kept = unmoved(e.from) && unmoved(e.to);
            let rect = |label: &Option<super::EdgeLabel>| label.as_ref().map(|l| l.rect);
            let labels = [rect(&old.label), rect(&old.tail_label), rect(&old.head_label)];
            kept.then(|| Drawn { route: old.points.clone(), labels })
        })
        .collect();
    let kept_routes = previous_routes.iter().flatten();
    let routes = Segments::new(kept_routes.clone().flat_map(|d| d.route.windows(2).map(|s| (s[0], s[1]))));
    let labels = kept_routes.flat_map(|d| d.labels.into_iter().flatten()).collect();
    let mut obstacles = Obstacles { routes, labels, linked: Vec::new(), corner };
    for i in 0..nodes.len() {
        if wanted[i] == Wanted::Free {
            let desired = beside_neighbours(i, fresh, &placed, edges, corner);
            let other_end = |e: &Edge| if e.from == i { e.to } else { e.from };
            let ends = edges.iter().filter(|e| (e.from == i) != (e.to == i)).map(other_end);
            obstacles.linked = ends.filter_map(|j| placed[j]).collect();
            placed[i] = Some(free_spot(at(i, desired), &placed, &obstacles));
        }
    }
    let boxes = placed.iter().zip(fresh).enumerate().map(|(i, (p, f))| p.unwrap_or(at(i, *f))).collect();
    (boxes, previous_routes)
}

/// Where a new node goes: at the offset from its placed neighbours that the fresh layout has
/// (below its superclass, after its predecessor), else where the fresh layout put it, moved as
/// the placed nodes moved on the whole.
fn beside_neighbours(i: usize, fresh: &[Point], placed: &[Option<Rect>], edges: &[Edge], corner: Point) -> Point {
    let shift = |j: usize| placed[j].map(|r| (r.x - fresh[j].x, r.y - fresh[j].y));
    let near: Vec<(f64, f64)> = edges
        .iter()
        .filter_map(|e| match (e.from == i, e.to == i) {
            (true, false) => shift(e.to),
            (false, true) => shift(e.from),
            _ => None,
        })
        .collect();
    let (dx, dy) = if near.is_empty() {
        let all: Vec<(f64, f64)> = (0..placed.len()).filter_map(shift).collect();
        (median(all.iter().map(|s| s.0)), median(all.iter().map(|s| s.1)))
    } else {
        let n = near.len() as f64;
        (near.iter().map(|s| s.0).sum::<f64>() / n, near.iter().map(|s| s.1).sum::<f64>() / n)
    };
    Point { x: (fresh[i].x + dx).max(corner.x), y: (fresh[i].y + dy).max(corner.y) }
}

fn median(values: impl Iterator<Item = f64>) -> f64 {
    let mut values: Vec<f64> = values.collect();
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// What a new node should not cover besides the placed nodes: the routes and labels kept.
#[derive(Default)]
struct Obstacles {
    routes: Segments,
    labels: Vec<Rect>,
    /// The placed nodes the new one has edges to: its straight routes to them should pass no
    /// other box.
    linked: Vec<Rect>,
    /// No spot is left of or above it.
    corner: Point,
}

/// The spot nearest `wanted` (searched in rings of `STEP`) where the box keeps `CLEARANCE`
/// from every placed box, covers no route or label of `obstacles` and its straight routes to
/// the linked nodes pass no other box; past `RINGS` rings, those are no obstacle; past twice
/// that, right of everything.
fn free_spot(wanted: Rect, placed: &[Option<Rect>], obstacles: &Obstacles) -> Rect {
    let boxes: Vec<Rect> = placed.iter().flatten().copied().collect();
    let clear_of_boxes = |r: &Rect| {
        // Clear by `CLEARANCE`, to rounding: a dataflow's ranks are exactly that far apart.
        let padded = r.grown(CLEARANCE - 0.01);
        !boxes.iter().any(|b| intersects(padded, *b))
    };
    let centre = |r: &Rect| Point { x: r.x + r.width / 2.0, y: r.y + r.height / 2.0 };
    let links_clear = |r: &Rect| {
        obstacles.linked.iter().all(|end| {
            let (a, b) = (centre(r), centre(end));
            !boxes.iter().any(|o| o != end && segment_meets_box(a, b, *o))
        })
    };
    let clear_of_obstacles =
        |r: &Rect| !obstacles.labels.iter().any(|l| intersects(*l, *r)) && !obstacles.routes.meet(*r) && links_clear(r);
    let found = around(wanted, STEP, 0..2 * RINGS)
        .filter(|(_, r)| r.x >= obstacles.corner.x - 1e-9 && r.y >= obstacles.corner.y - 1e-9)
        .find(|(ring, r)| clear_of_boxes(r) && (*ring >= RINGS || clear_of_obstacles(r)));
    if let Some((_, spot)) = found {
        return spot;
    }
    let right = boxes.iter().map(|b| b.x + b.width).fold(obstacles.corner.x, f64::max);
    Rect { x: right + CLEARANCE, ..wanted }
}

/// Per edge, how far its route bows out of the line between its boxes' centres, to one side of
/// the line from the box of lower index to the other: 0 for an edge alone; edges between the
/// same two boxes at least `FAN` apart and room for their end labels between them, centred on
/// that line.
fn fan_positions(edges: &[Edge]) -> Vec<f64> {
    let mut offsets = vec![0.0; edges.len()];
    for members in parallel_edges(edges.iter().map(|e| (e.from, e.to))) {
        let middle = (members.len() as f64 - 1.0) / 2.0;
        let step = members.iter().map(|&k| edges[k].end_label_width + 16.0).fold(FAN, f64::max);
        for (i, &k) in members.iter().enumerate() {
            let turned = if edges[k].from > edges[k].to { -1.0 } else { 1.0 };
            offsets[k] = (i as f64 - middle) * step * turned;
        }
    }
    offsets
}

/// A route drawn anew for edge `e` among the placed boxes: the straight one (`straight`), or
/// where that passes another box, one around them (`detour`) if there is one.
fn anew(obstacles: &detour::Obstacles, e: &Edge, fan: f64) -> Vec<Point> {
    let line = straight(obstacles.boxes[e.from], obstacles.boxes[e.to], fan);
    if fan != 0.0 || e.from == e.to || !obstacles.blocks(&line, e.from, e.to) {
        return line;
    }
    obstacles.around(e.from, e.to).unwrap_or(line)
}

/// How far apart the routes of edges between the same two boxes bow out at least.
const FAN: f64 = 40.0;

/// A route from the border of `from` to the border of `to`: the line between their centres, or
/// for a parallel edge (`fan` off that line, `fan_positions`) two lines through a point that far
/// off the line's middle; a loop where they are one box.
fn straight(from: Rect, to: Rect, fan: f64) -> Vec<Point> {
    if from == to {
        return self_loop(from.x + from.width, from.y + from.height / 2.0, from.height);
    }
    let centre = |r: Rect| Point { x: r.x + r.width / 2.0, y: r.y + r.height / 2.0 };
    let (a, b) = (centre(from), centre(to));
    let length = (b.x - a.x).hypot(b.y - a.y);
    if fan == 0.0 || length < 1e-9 {
        return vec![border_towards(from, a, b), border_towards(to, b, a)];
    }
    let off = fan / length;
    let bend = Point { x: (a.x + b.x) / 2.0 + (a.y - b.y) * off, y: (a.y + b.y) / 2.0 + (b.x - a.x) * off };
    vec![border_towards(from, a, bend), bend, border_towards(to, b, bend)]
}

/// Where the ray from `centre` (of `r`) towards `to` leaves `r`.
fn border_towards(r: Rect, centre: Point, to: Point) -> Point {
    let (dx, dy) = (to.x - centre.x, to.y - centre.y);
    let tx = if dx.abs() > 1e-9 { r.width / 2.0 / dx.abs() } else { f64::INFINITY };
    let ty = if dy.abs() > 1e-9 { r.height / 2.0 / dy.abs() } else { f64::INFINITY };
    let t = tx.min(ty).min(1.0);
    Point { x: centre.x + dx * t, y: centre.y + dy * t }
}
