//! The tree check of [`ModelBuilder`](crate::ModelBuilder): roots, the depth-first order, and
//! the links that cannot be reached from a root, told apart as orphans or cycles.

use crate::error::Issue;

/// The parent of a link as the joints declare it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ParentRef {
    /// No joint has this link as its child.
    None,
    /// The world datum, through joint `joint`.
    World { joint: usize },
    /// Link `link`, through joint `joint`.
    Link { joint: usize, link: usize },
    /// A parent name that is neither a link nor the world, through joint `joint`.
    Unknown { joint: usize },
}

/// What became of a link that no root reaches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fate {
    Unknown,
    Reached,
    Orphan,
    Cycle,
}

/// The traversal order and the topology problems of a set of links.
pub(crate) struct Order {
    /// Input link indices, depth-first from the roots (the parentless link first, then the
    /// world-attached links in declaration order).
    pub links: Vec<usize>,
    /// Input joint indices in the same order (the joint attaching each link, when it has one).
    pub joints: Vec<usize>,
}

/// Orders the links depth-first and reports several parentless links, no root at all, and
/// cycles. Orphans (links below a joint whose parent does not exist) are not cycles: their
/// joints are reported as [`Issue::UnknownParent`] by the caller, and nothing more here.
///
/// `parent` is the first parent of each link; `children[l]` the joints whose parent is link `l`
/// (declaration order), `world_joints` those whose parent is the world, `child_of[j]` each
/// joint's child link (when it exists); `several_parents` is set when some link has several
/// parent joints (then cycles are not looked for: the tree is already broken).
pub(crate) fn order(
    names: &[&str],
    parent: &[ParentRef],
    children: &[Vec<usize>],
    world_joints: &[usize],
    child_of: &[Option<usize>],
    several_parents: bool,
    issues: &mut Vec<Issue>,
) -> Order {
    let n = names.len();
    let roots: Vec<usize> = (0..n).filter(|&l| parent[l] == ParentRef::None).collect();
    if roots.len() > 1 {
        issues.push(Issue::MultipleRoots {
            links: roots.iter().map(|&l| names[l].to_string()).collect(),
        });
    }
    let mut out = Order {
        links: Vec::with_capacity(n),
        joints: Vec::new(),
    };
    let mut fate = vec![Fate::Unknown; n];
    // Depth-first from the parentless root, then from each world-attached link.
    let mut starts: Vec<(usize, Option<usize>)> =
        roots.first().map(|&r| (r, None)).into_iter().collect();
    starts.extend(
        world_joints
            .iter()
            .filter_map(|&j| child_of[j].map(|c| (c, Some(j)))),
    );
    for start in starts {
        let mut stack = vec![start];
        while let Some((l, via)) = stack.pop() {
            if fate[l] == Fate::Reached {
                continue;
            }
            fate[l] = Fate::Reached;
            out.links.push(l);
            out.joints.extend(via);
            for &j in children[l].iter().rev() {
                if let Some(c) = child_of[j] {
                    stack.push((c, Some(j)));
                }
            }
        }
    }
    if n > 0 && roots.is_empty() && world_joints.is_empty() {
        // Only a missing root or a cycle can leave no start at all; an orphan alone explains it.
        let orphan = parent
            .iter()
            .any(|p| matches!(p, ParentRef::Unknown { .. }));
        if !orphan {
            issues.push(Issue::NoRoot);
        }
    }
    if several_parents || roots.len() > 1 {
        return out;
    }
    // Classify each unreached link by walking up its parents.
    let mut on_walk = vec![false; n];
    for l in 0..n {
        if fate[l] != Fate::Unknown {
            continue;
        }
        let mut walk = Vec::new();
        let mut x = l;
        let result = loop {
            if fate[x] != Fate::Unknown {
                break fate[x];
            }
            if on_walk[x] {
                issues.push(Issue::Cycle {
                    link: names[x].to_string(),
                });
                break Fate::Cycle;
            }
            on_walk[x] = true;
            walk.push(x);
            match parent[x] {
                ParentRef::Link { link, .. } => x = link,
                ParentRef::Unknown { .. } => break Fate::Orphan,
                // Reached links never get here; a parentless or world-attached link is a start.
                ParentRef::None | ParentRef::World { .. } => break Fate::Reached,
            }
        };
        for w in walk {
            fate[w] = result;
            on_walk[w] = false;
        }
    }
    out
}
