//! The frame graph of an SDFormat document: every named frame (the world, models, links, joints,
//! `<frame>`s) with its pose relative to another frame, the scopes names are looked up in, and
//! the attachment of frames to links.

use super::read::{Located, Res, fail};
use crate::xml_tree::Element;
use kinetree_spatial::Se3;
use std::collections::HashMap;

/// What a frame of the graph is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    World,
    Model,
    Link,
    Joint,
    Frame,
}

/// One frame.
pub(crate) struct Node<'a> {
    pub(crate) kind: Kind,
    /// The scope (model, or 0 for the world) the element is declared in.
    pub(crate) scope: usize,
    /// Its name within that scope.
    pub(crate) name: String,
    pub(crate) e: &'a Element,
    /// Its pose relative to the frame `relative_to` names (its default when `None`).
    pub(crate) pose: Se3,
    pub(crate) relative_to: Option<String>,
    /// A `<frame>`'s `attached_to`; a joint's child link (the default of its pose).
    pub(crate) attached_to: Option<String>,
    /// The frame `pose` is relative to, once resolved.
    pub(crate) parent: usize,
    /// For a model, the scope it opens.
    pub(crate) inner: Option<usize>,
}

/// A model's name scope (scope 0 is the world's).
pub(crate) struct Scope<'a> {
    pub(crate) e: &'a Element,
    /// The model frame (`__model__`); the world node for scope 0.
    pub(crate) node: usize,
    /// Prefix of the kinetree names of its items (`""`, `"arm::"`).
    pub(crate) prefix: String,
    pub(crate) names: HashMap<String, usize>,
    pub(crate) links: Vec<usize>,
    /// Nested models' scopes, in document order.
    pub(crate) models: Vec<usize>,
    pub(crate) is_static: bool,
    pub(crate) canonical: Option<String>,
    pub(crate) placement_frame: Option<String>,
}

pub(crate) struct Graph<'a> {
    pub(crate) nodes: Vec<Node<'a>>,
    pub(crate) scopes: Vec<Scope<'a>>,
}

fn pose_element(e: &Element) -> &Element {
    e.children.iter().find(|c| c.name == "pose").unwrap_or(e)
}

impl<'a> Graph<'a> {
    /// The graph with only the world frame and scope.
    pub(crate) fn new(root: &'a Element) -> Self {
        Self {
            nodes: vec![Node {
                kind: Kind::World,
                scope: 0,
                name: "world".to_string(),
                e: root,
                pose: Se3::IDENTITY,
                relative_to: None,
                attached_to: None,
                parent: 0,
                inner: Some(0),
            }],
            scopes: vec![Scope {
                e: root,
                node: 0,
                prefix: String::new(),
                names: HashMap::new(),
                links: Vec::new(),
                models: Vec::new(),
                is_static: false,
                canonical: None,
                placement_frame: None,
            }],
        }
    }

    /// Adds a frame and its name in its scope.
    ///
    /// A name used twice in one scope is an error, except a link and a joint of the same name
    /// (allowed before SDFormat 1.7), where the link keeps the name for lookups.
    pub(crate) fn add_node(&mut self, node: Node<'a>) -> Res<usize> {
        let id = self.nodes.len();
        let scope = &mut self.scopes[node.scope];
        match scope.names.get(&node.name) {
            Some(&other) => {
                let kinds = (self.nodes[other].kind, node.kind);
                match kinds {
                    (Kind::Link, Kind::Joint) => {}
                    (Kind::Joint, Kind::Link) => {
                        scope.names.insert(node.name.clone(), id);
                    }
                    _ => {
                        return fail(
                            node.e,
                            format!(
                                "the name '{}' is already used in this scope (line {})",
                                node.name, self.nodes[other].e.line
                            ),
                        );
                    }
                }
            }
            None => {
                scope.names.insert(node.name.clone(), id);
            }
        }
        self.nodes.push(node);
        Ok(id)
    }

    pub(crate) fn add_scope(&mut self, scope: Scope<'a>) -> usize {
        self.scopes.push(scope);
        self.scopes.len() - 1
    }

    /// The frame `name` names in `scope`: `__model__`, `world`, an item's name, or a path
    /// through nested models (`arm::link`).
    pub(crate) fn lookup(&self, scope: usize, name: &str) -> Option<usize> {
        match name {
            "__model__" => return Some(self.scopes[scope].node),
            "world" => return Some(0),
            _ => {}
        }
        if let Some((first, rest)) = name.split_once("::") {
            let &n = self.scopes[scope].names.get(first)?;
            let inner = self.nodes[n]
                .inner
                .filter(|_| self.nodes[n].kind == Kind::Model)?;
            return self.lookup(inner, rest);
        }
        self.scopes[scope].names.get(name).copied()
    }

    pub(crate) fn lookup_or_fail(&self, scope: usize, name: &str, e: &Element) -> Res<usize> {
        match self.lookup(scope, name) {
            Some(n) => Ok(n),
            None => fail(
                e,
                format!(
                    "'{name}' names no frame in {}",
                    self.scope_description(scope)
                ),
            ),
        }
    }

    fn scope_description(&self, scope: usize) -> String {
        if scope == 0 {
            "the world".to_string()
        } else {
            format!("model '{}'", self.nodes[self.scopes[scope].node].name)
        }
    }

    /// Resolves every pose's frame, refuses cycles, and folds each model's `placement_frame`
    /// into its pose.
    pub(crate) fn resolve(&mut self) -> Res<()> {
        for id in 1..self.nodes.len() {
            let n = &self.nodes[id];
            let scope = n.scope;
            let parent = match (&n.relative_to, n.kind) {
                (Some(r), _) => self.lookup_or_fail(scope, r, pose_element(n.e))?,
                (None, Kind::Joint) => {
                    let child = n.attached_to.as_deref().unwrap_or_default();
                    match self.lookup(scope, child) {
                        Some(c) if c != 0 => c,
                        _ => {
                            return fail(
                                n.e,
                                format!(
                                    "child '{child}' names no link in {}",
                                    self.scope_description(scope)
                                ),
                            );
                        }
                    }
                }
                (None, Kind::Frame) => match &n.attached_to {
                    Some(a) => self.lookup_or_fail(scope, a, n.e)?,
                    None => self.scopes[scope].node,
                },
                (None, _) => self.scopes[scope].node,
            };
            if parent == id {
                return fail(
                    pose_element(n.e),
                    format!("the pose of '{}' is relative to itself", n.name),
                );
            }
            self.nodes[id].parent = parent;
        }
        // Cycles: 0 unvisited, 1 on the current walk, 2 reaches the world.
        let mut state = vec![0u8; self.nodes.len()];
        state[0] = 2;
        for start in 0..self.nodes.len() {
            let mut walk = Vec::new();
            let mut at = start;
            while state[at] == 0 {
                state[at] = 1;
                walk.push(at);
                at = self.nodes[at].parent;
            }
            if state[at] == 1 {
                let n = &self.nodes[at];
                return fail(
                    pose_element(n.e),
                    format!(
                        "the poses of '{}' and its relative_to frames form a cycle",
                        n.name
                    ),
                );
            }
            for w in walk {
                state[w] = 2;
            }
        }
        // Placement frames, innermost models first.
        for id in (1..self.nodes.len()).rev() {
            let Some(inner) = self.nodes[id].inner else {
                continue;
            };
            let Some(pf) = self.scopes[inner].placement_frame.clone() else {
                continue;
            };
            let e = self.nodes[id].e;
            let target = self.lookup_or_fail(inner, &pf, e)?;
            let mut model_from_frame = Se3::IDENTITY;
            let mut at = target;
            while at != id {
                if at == 0 {
                    return fail(
                        e,
                        format!("placement_frame '{pf}' is not placed inside the model"),
                    );
                }
                model_from_frame = self.nodes[at].pose * model_from_frame;
                at = self.nodes[at].parent;
            }
            self.nodes[id].pose *= model_from_frame.inverse();
        }
        Ok(())
    }

    /// `n`, the frame its pose is relative to, and so on up to the world.
    fn chain(&self, mut n: usize) -> Vec<usize> {
        let mut out = vec![n];
        while n != 0 {
            n = self.nodes[n].parent;
            out.push(n);
        }
        out
    }

    /// The pose of frame `b` in frame `a` (`a_from_b`) at zero configuration, composed through
    /// their closest common frame (so that a pose written relative to `a` comes back exactly).
    pub(crate) fn relative(&self, a: usize, b: usize) -> Se3 {
        let (ca, cb) = (self.chain(a), self.chain(b));
        let (mut i, mut j) = (ca.len(), cb.len());
        while i > 0 && j > 0 && ca[i - 1] == cb[j - 1] {
            i -= 1;
            j -= 1;
        }
        let down = |c: &[usize]| {
            c.iter()
                .rev()
                .fold(None, |acc: Option<Se3>, &n| {
                    Some(acc.map_or(self.nodes[n].pose, |x| x * self.nodes[n].pose))
                })
                .unwrap_or(Se3::IDENTITY)
        };
        let (lca_from_a, lca_from_b) = (down(&ca[..i]), down(&cb[..j]));
        if i == 0 {
            lca_from_b
        } else {
            lca_from_a.inverse() * lca_from_b
        }
    }

    /// The link frame `n` moves with (`None`: the world).
    pub(crate) fn attached_link(&self, n: usize) -> Res<Option<usize>> {
        let mut at = n;
        for _ in 0..=self.nodes.len() {
            let node = &self.nodes[at];
            at = match node.kind {
                Kind::Link => return Ok(Some(at)),
                Kind::World => return Ok(None),
                Kind::Joint => node.parent_child(self)?,
                Kind::Frame => match &node.attached_to {
                    Some(a) => self.lookup_or_fail(node.scope, a, node.e)?,
                    None => self.scopes[node.scope].node,
                },
                Kind::Model => self.canonical(node.inner.unwrap_or(0))?,
            };
        }
        let node = &self.nodes[n];
        fail(
            node.e,
            format!("the attached_to chain of '{}' forms a cycle", node.name),
        )
    }

    /// A model's canonical link: `canonical_link`, else its first link, else its first nested
    /// model's.
    fn canonical(&self, scope: usize) -> Res<usize> {
        let s = &self.scopes[scope];
        if let Some(name) = &s.canonical {
            let n = self.lookup_or_fail(scope, name, s.e)?;
            if self.nodes[n].kind != Kind::Link {
                return fail(s.e, format!("canonical_link '{name}' is not a link"));
            }
            return Ok(n);
        }
        if let Some(&l) = s.links.first() {
            return Ok(l);
        }
        match s.models.first() {
            Some(&m) => self.canonical(m),
            None => fail(s.e, "the model has no link"),
        }
    }

    /// The link a joint's `<parent>` or `<child>` names (a link, or a frame attached to one;
    /// `None` for `world`, allowed only when `world_ok`).
    pub(crate) fn joint_end(
        &self,
        scope: usize,
        name: &str,
        e: &Element,
        world_ok: bool,
    ) -> Res<Option<usize>> {
        let n = self.lookup_or_fail(scope, name, e)?;
        match self.attached_link(n)? {
            Some(l) => Ok(Some(l)),
            None if world_ok => Ok(None),
            None => fail(e, format!("'{name}' is the world, not a link")),
        }
    }
}

impl Node<'_> {
    /// A joint's child link frame (the frame its pose defaults to).
    fn parent_child(&self, graph: &Graph<'_>) -> Result<usize, Located> {
        let child = self.attached_to.as_deref().unwrap_or_default();
        graph.lookup_or_fail(self.scope, child, self.e)
    }
}
