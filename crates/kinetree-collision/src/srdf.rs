//! SRDF (MoveIt's Semantic Robot Description Format): reading and writing
//! `<disable_collisions>` entries.

use crate::error::CollisionError;
use crate::model::CollisionModel;
use kinetree_kinematics::model::{MAX_XML_DEPTH, Model};
use quick_xml::events::Event;

/// A `<disable_collisions link1=".." link2=".." reason=".."/>` entry.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DisabledPair {
    /// First link name.
    pub link1: String,
    /// Second link name.
    pub link2: String,
    /// MoveIt's reason (`Adjacent`, `Default`, `Always`, `Never`, `User`), empty when absent.
    pub reason: String,
}

/// Every `<disable_collisions>` entry of an SRDF document, in document order. Other elements
/// (groups, end effectors, virtual joints, …) are ignored.
///
/// # Errors
/// [`CollisionError::Srdf`] for malformed XML or an entry without `link1`/`link2`.
///
/// # Examples
/// ```
/// use kinetree_collision::srdf::parse_disabled_pairs;
/// # fn main() -> Result<(), kinetree_collision::CollisionError> {
/// let srdf = r#"<robot name="r">
///   <disable_collisions link1="a" link2="b" reason="Never"/>
/// </robot>"#;
/// let pairs = parse_disabled_pairs(srdf)?;
/// assert_eq!((pairs[0].link1.as_str(), pairs[0].link2.as_str()), ("a", "b"));
/// # Ok(())
/// # }
/// ```
pub fn parse_disabled_pairs(srdf: &str) -> Result<Vec<DisabledPair>, CollisionError> {
    let mut reader = quick_xml::Reader::from_str(srdf);
    let mut out = Vec::new();
    let mut depth = 0usize;
    loop {
        let position = reader.buffer_position();
        let event = reader.read_event().map_err(|e| CollisionError::Srdf {
            position: reader.error_position(),
            message: e.to_string(),
        })?;
        let element = match &event {
            Event::Start(e) => {
                depth += 1;
                if depth > MAX_XML_DEPTH {
                    return Err(CollisionError::Srdf {
                        position,
                        message: format!("elements nested deeper than {MAX_XML_DEPTH} levels"),
                    });
                }
                e
            }
            Event::Empty(e) => e,
            Event::End(_) => {
                depth = depth.saturating_sub(1);
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        if element.local_name().as_ref() != b"disable_collisions" {
            continue;
        }
        let attribute = |name: &str| -> Result<Option<String>, CollisionError> {
            let attr = element
                .try_get_attribute(name)
                .map_err(|e| CollisionError::Srdf {
                    position,
                    message: e.to_string(),
                })?;
            attr.map(|a| {
                a.unescape_value()
                    .map(|v| v.into_owned())
                    .map_err(|e| CollisionError::Srdf {
                        position,
                        message: e.to_string(),
                    })
            })
            .transpose()
        };
        let required = |name: &str| {
            attribute(name)?.ok_or_else(|| CollisionError::Srdf {
                position,
                message: format!("<disable_collisions> without '{name}'"),
            })
        };
        out.push(DisabledPair {
            link1: required("link1")?,
            link2: required("link2")?,
            reason: attribute("reason")?.unwrap_or_default(),
        });
    }
    Ok(out)
}

/// Writes `<disable_collisions>` lines for `pairs`, one per line, ready to paste into an SRDF
/// `<robot>` element.
#[must_use]
pub fn write_disabled_pairs(pairs: &[DisabledPair]) -> String {
    use quick_xml::escape::escape;
    let mut out = String::new();
    for p in pairs {
        out.push_str(&format!(
            "<disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>\n",
            escape(p.link1.as_str()),
            escape(p.link2.as_str()),
            escape(p.reason.as_str())
        ));
    }
    out
}

impl CollisionModel {
    /// Disables the link pairs listed in an SRDF document's `<disable_collisions>` entries (see
    /// [`parse_disabled_pairs`]) and returns the number of shape pairs removed, as Pinocchio's
    /// `removeCollisionPairs(model, geom_model, srdf)`.
    ///
    /// # Errors
    /// [`CollisionError::Srdf`]; [`CollisionError::UnknownLink`] for an entry naming a link the
    /// model does not have (nothing is changed then).
    pub fn disable_pairs_from_srdf_str(
        &mut self,
        model: &Model,
        srdf: &str,
    ) -> Result<usize, CollisionError> {
        let pairs = parse_disabled_pairs(srdf)?;
        self.disable_link_pairs(
            model,
            pairs.iter().map(|p| (p.link1.as_str(), p.link2.as_str())),
        )
    }

    /// Reads an SRDF file and disables its pairs (see
    /// [`CollisionModel::disable_pairs_from_srdf_str`]).
    ///
    /// # Errors
    /// [`CollisionError::Srdf`] when the file cannot be read, and the errors of
    /// [`CollisionModel::disable_pairs_from_srdf_str`].
    pub fn disable_pairs_from_srdf_file(
        &mut self,
        model: &Model,
        path: impl AsRef<std::path::Path>,
    ) -> Result<usize, CollisionError> {
        let text = std::fs::read_to_string(path.as_ref()).map_err(|e| CollisionError::Srdf {
            position: 0,
            message: format!("{}: {e}", path.as_ref().display()),
        })?;
        self.disable_pairs_from_srdf_str(model, &text)
    }
}
