//! A CPU model of pruning (docs/src/pruning.md), for the sorted map's tests: which of a
//! texel's collected ranges the sort keeps. Written from the rules as the doc states them,
//! not from the shader's loops: the static rule, then (with `Pruning::Cover`) the cover
//! rule's sweep over the ranges the static rule kept, with each triangle's best reach
//! gathered in a map. Its arithmetic is
//! the same f32 operations in the same order as the shader's (`precise` there), so that the
//! two agree bit for bit on which ranges a margin test keeps.

use motion_shadows::technique::{Pruning, Range, gpu_constants};
use std::collections::HashMap;

/// The shaders' PRUNE_MARGIN (the generated constants).
const MARGIN: f32 = gpu_constants::PRUNE_MARGIN;
/// The shaders' PRUNE_BUDGET: the sweep's loop iterations per texel (a range added to the
/// candidates, a candidate visited, a step closed: one each; `Candidates`).
pub const BUDGET: usize = gpu_constants::PRUNE_BUDGET as usize;

/// What the sort keeps of one texel's ranges.
pub struct Pruned {
    /// The kept ranges, in the sort's order.
    pub kept: Vec<Range>,
    /// Dropped by the static rule (behind the static layer, plane test only).
    pub by_static: usize,
    /// Dropped by the cover rule, or by the coverage rule.
    pub by_cover: usize,
    /// Whether the sweep ran out of its budget (the undecided ranges kept).
    pub out_of_budget: bool,
    /// The sweep's steps (the budget's unit).
    pub steps: usize,
}

/// A linear depth over a closed time interval: a range, or the static layer over [0, 1].
#[derive(Clone, Copy)]
struct Line {
    t: (f32, f32),
    d: (f32, f32),
}

impl Line {
    fn of(r: &Range) -> Line {
        Line {
            t: (r.t_s, r.t_e),
            d: (r.d_s, r.d_e),
        }
    }

    /// The depth at `at` (a lookup's interpolation; a zero-length line has its first depth).
    fn depth(&self, at: f32) -> f32 {
        if at <= self.t.0 {
            self.d.0
        } else if at >= self.t.1 {
            self.d.1
        } else {
            self.d.0 + (self.d.1 - self.d.0) * ((at - self.t.0) / (self.t.1 - self.t.0))
        }
    }

    fn max_abs(&self) -> f32 {
        self.d.0.abs().max(self.d.1.abs())
    }
}

/// How much nearer to the light than `r` the cover `q` is at `at`.
fn gap(q: Line, r: Line, at: f32) -> f32 {
    r.depth(at) - q.depth(at)
}

/// The latest time from `tau` up to which `q` is checked to be nearer than `r` by the margin
/// (at tau and there: both are linear in between); None where q is no cover at tau.
fn reach(q: Line, r: Line, tau: f32) -> Option<f32> {
    if q.t.0 > tau || q.t.1 < tau {
        return None;
    }
    let m = MARGIN * r.max_abs().max(q.max_abs()).max(1.0);
    if gap(q, r, tau) <= m {
        return None;
    }
    let end = q.t.1.min(r.t.1);
    let gap_end = gap(q, r, end);
    if gap_end > m {
        return Some(end);
    }
    // Where the gap falls to 2m on the line through the pair's common start and `end`.
    let lo = q.t.0.max(r.t.0);
    let g0 = gap(q, r, lo) - 2.0 * m;
    let g1 = gap_end - 2.0 * m;
    if g0 <= 0.0 {
        return Some(tau);
    }
    let x = lo + g0 / (g0 - g1) * (end - lo);
    Some(if x > tau && gap(q, r, x) > m { x } else { tau })
}

/// Whether no two of a texel's ranges of one triangle hold at the same time (the exact
/// collection's runs are separated by a piece of positive length): the premise of the cover
/// rule's proof that the nearest range at any time is not of the dropped range's triangle,
/// and the reason its test of distinct triangles never decides anything there.
pub fn runs_disjoint(ranges: &[Range]) -> bool {
    ranges.iter().enumerate().all(|(i, a)| {
        ranges[i + 1..]
            .iter()
            .all(|b| a.id != b.id || a.t_e < b.t_s || b.t_e < a.t_s)
    })
}

/// Takes a cover's reach as its triangle's best.
fn offer(best: &mut HashMap<u32, f32>, id: u32, reach: Option<f32>) {
    if let Some(reach) = reach {
        let at = best.entry(id).or_insert(reach);
        *at = at.max(reach);
    }
}

/// The second-largest of the triangles' best reaches (-1: fewer than two).
fn second_best(best: &HashMap<u32, f32>) -> f32 {
    let mut reaches: Vec<f32> = best.values().copied().collect();
    reaches.sort_by(|a, b| b.partial_cmp(a).unwrap());
    reaches.get(1).copied().unwrap_or(-1.0)
}

/// The shader's candidate list, for the budget alone (its loop iterations; the decisions
/// above do not depend on it): the ranges added so far, in the shader's order.
#[derive(Default)]
struct Candidates {
    list: Vec<usize>,
    added: usize,
}

impl Candidates {
    /// The iterations of one step of range `i` at tau: one per range that starts by tau
    /// added to the list, one per candidate visited (one that ended before r's start taken
    /// out, the last put in its place), until two covers reach r's end, and one to close.
    fn step_cost(
        &mut self,
        ranges: &[Range],
        i: usize,
        tau: f32,
        static_line: Option<(u32, Line)>,
    ) -> usize {
        let r = &ranges[i];
        let line = Line::of(r);
        let mut cost = 0;
        while self.added < ranges.len() && ranges[self.added].t_s <= tau {
            self.list.push(self.added);
            self.added += 1;
            cost += 1;
        }
        let mut best: HashMap<u32, f32> = HashMap::new();
        if let Some((id, s)) = static_line {
            offer(&mut best, id, reach(s, line, tau));
        }
        let mut j = 0;
        while j < self.list.len() {
            cost += 1;
            let q = &ranges[self.list[j]];
            if q.t_e < r.t_s {
                self.list.swap_remove(j);
                continue;
            }
            j += 1;
            if q.id != r.id {
                offer(&mut best, q.id, reach(Line::of(q), line, tau));
                if second_best(&best) >= r.t_e {
                    break;
                }
            }
        }
        cost + 1
    }
}

/// The coverage rule (the coverage map in the sort): of the sorted `ranges`, the first that
/// holds the texel over [0, 1] with every other range farther than it at both of that range's
/// ends, by the margin, alone; or all of them. (The static layer plays no part: where it is
/// nearer it shadows first.)
fn keep_covering_range(ranges: &[Range]) -> Vec<Range> {
    let reach = |front: f32| front + MARGIN * front.abs().max(1.0);
    let behind = |c: &Range, q: &Range| {
        let at = |t: f32| c.d_s + t * (c.d_e - c.d_s);
        q.d_s > reach(at(q.t_s)) && q.d_e > reach(at(q.t_e))
    };
    ranges
        .iter()
        .enumerate()
        .find(|(i, c)| {
            (c.t_s, c.t_e) == (0.0, 1.0)
                && ranges
                    .iter()
                    .enumerate()
                    .all(|(j, q)| j == *i || behind(c, q))
        })
        .map_or_else(|| ranges.to_vec(), |(_, c)| vec![*c])
}

/// The sort's order: (t_s, t_e, d_s, d_e, id).
fn sort_key(r: &Range) -> (f32, f32, f32, f32, u32) {
    (r.t_s, r.t_e, r.d_s, r.d_e, r.id)
}

/// What the sort keeps of `ranges` (a texel's, as collected) with static-layer triangle
/// `static_layer` (id, depth), receivers tested at their plane's depth or not, by the rule
/// `pruning`.
pub fn prune(
    ranges: &[Range],
    static_layer: Option<(u32, f32)>,
    plane_test: bool,
    pruning: Pruning,
) -> Pruned {
    let behind_static = |r: &Range| match static_layer {
        Some((_, d)) if plane_test => r.d_s.min(r.d_e) > d + MARGIN * d.abs().max(1.0),
        _ => false,
    };
    let collected = ranges.len();
    let mut ranges: Vec<Range> = ranges
        .iter()
        .copied()
        .filter(|r| !behind_static(r))
        .collect();
    ranges.sort_by(|a, b| sort_key(a).partial_cmp(&sort_key(b)).unwrap());
    let statically_kept = ranges.len();
    let static_line = static_layer.map(|(id, d)| {
        (
            id,
            Line {
                t: (0.0, 1.0),
                d: (d, d),
            },
        )
    });

    let mut keep = vec![true; ranges.len()];
    let mut spent = 0;
    let mut out_of_budget = false;
    let mut candidates = Candidates::default();
    if pruning == Pruning::Coverage {
        let kept = keep_covering_range(&ranges);
        return Pruned {
            by_static: collected - statically_kept,
            by_cover: statically_kept - kept.len(),
            kept,
            out_of_budget: false,
            steps: 0,
        };
    }
    let swept = match pruning {
        Pruning::StaticLayer | Pruning::Coverage => 0,
        Pruning::Cover => ranges.len(),
    };
    'ranges: for (i, r) in ranges.iter().enumerate().take(swept) {
        let line = Line::of(r);
        let mut tau = r.t_s;
        loop {
            // Each triangle's best reach at tau among its covers (never r's own triangle),
            // from every range that starts by tau (those that have ended offer nothing).
            let mut best: HashMap<u32, f32> = HashMap::new();
            if let Some((id, s)) = static_line {
                offer(&mut best, id, reach(s, line, tau));
            }
            for q in ranges.iter().take_while(|q| q.t_s <= tau) {
                if q.id != r.id {
                    offer(&mut best, q.id, reach(Line::of(q), line, tau));
                }
            }
            spent += candidates.step_cost(&ranges, i, tau, static_line);
            if spent > BUDGET {
                out_of_budget = true;
                break 'ranges;
            }
            let second = second_best(&best);
            if second >= r.t_e {
                keep[i] = false;
                continue 'ranges;
            }
            if second <= tau {
                continue 'ranges;
            }
            tau = second;
        }
    }
    let kept: Vec<Range> = (ranges.iter().zip(&keep))
        .filter(|(_, k)| **k)
        .map(|(r, _)| *r)
        .collect();
    Pruned {
        by_static: collected - statically_kept,
        by_cover: statically_kept - kept.len(),
        kept,
        out_of_budget,
        steps: spent,
    }
}
