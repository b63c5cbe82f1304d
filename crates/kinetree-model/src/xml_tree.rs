//! A small owned XML element tree for the readers that interpret whole documents (MJCF,
//! SDFormat), built with quick-xml without recursion, with a nesting limit and the line of every
//! element.

use quick_xml::events::{BytesStart, Event};

/// The deepest element nesting every XML reader accepts (URDF, MJCF, SDFormat, SRDF), as
/// tinyxml2's (MuJoCo's XML parser) limit: deeper documents are refused with an error, before
/// any recursion, instead of exhausting the stack of the code that walks the tree.
pub const MAX_XML_DEPTH: usize = 500;

/// One XML element: its name, attributes in document order, child elements, the 1-based line of
/// its start tag and its own text content (MJCF carries none that matters; SDFormat puts every
/// value there).
#[derive(Clone, Debug, Default)]
pub(crate) struct Element {
    pub(crate) name: String,
    pub(crate) attrs: Vec<(String, String)>,
    pub(crate) children: Vec<Element>,
    /// The element's own text (character data and CDATA directly inside it, entities resolved),
    /// as written, untrimmed.
    pub(crate) text: String,
    pub(crate) line: usize,
    /// Index of the file the element came from, in the reader's own list of files.
    pub(crate) file: usize,
}

impl Element {
    /// The value of attribute `name`, if present.
    pub(crate) fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

/// Why a document could not be turned into a tree, with the 1-based line and column.
#[derive(Debug)]
pub(crate) struct XmlError {
    pub(crate) line: usize,
    pub(crate) column: usize,
    pub(crate) message: String,
}

/// Counts lines up to increasing byte offsets in linear time overall.
struct LineCounter<'a> {
    text: &'a [u8],
    offset: usize,
    line: usize,
}

impl LineCounter<'_> {
    fn line_at(&mut self, offset: usize) -> usize {
        let offset = offset.min(self.text.len());
        if offset >= self.offset {
            self.line += self.text[self.offset..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
        } else {
            self.line = self.text[..offset].iter().filter(|&&b| b == b'\n').count() + 1;
        }
        self.offset = offset;
        self.line
    }
}

fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = before.iter().rev().take_while(|&&b| b != b'\n').count() + 1;
    (line, column)
}

fn start_element(
    start: &BytesStart<'_>,
    line: usize,
    file: usize,
    text: &str,
    offset: usize,
) -> Result<Element, XmlError> {
    let fail = |message: String| {
        let (line, column) = line_column(text, offset);
        XmlError {
            line,
            column,
            message,
        }
    };
    let name = String::from_utf8_lossy(start.name().as_ref()).into_owned();
    let mut attrs = Vec::new();
    for attr in start.attributes() {
        let attr = attr.map_err(|e| fail(format!("<{name}>: {e}")))?;
        let key = String::from_utf8_lossy(attr.key.as_ref()).into_owned();
        let value = attr
            .unescape_value()
            .map_err(|e| fail(format!("<{name} {key}=…>: {e}")))?
            .into_owned();
        if attrs.iter().any(|(k, _)| *k == key) {
            return Err(fail(format!("<{name}>: duplicated attribute '{key}'")));
        }
        attrs.push((key, value));
    }
    Ok(Element {
        name,
        attrs,
        children: Vec::new(),
        text: String::new(),
        line,
        file,
    })
}

fn encoding(text: &str, offset: usize, e: &dyn std::fmt::Display) -> XmlError {
    let (line, column) = line_column(text, offset);
    XmlError {
        line,
        column,
        message: e.to_string(),
    }
}

/// Parses `text` into its root element (the first top-level element), every element tagged with
/// `file`.
///
/// # Errors
/// Malformed XML, no root element, or nesting deeper than [`MAX_XML_DEPTH`].
pub(crate) fn parse(text: &str, file: usize) -> Result<Element, XmlError> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut lines = LineCounter {
        text: text.as_bytes(),
        offset: 0,
        line: 1,
    };
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    loop {
        let offset = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
        let event = reader.read_event().map_err(|e| {
            let (line, column) = line_column(text, reader.error_position() as usize);
            XmlError {
                line,
                column,
                message: e.to_string(),
            }
        })?;
        match event {
            Event::Start(s) | Event::Empty(s) if root.is_some() && stack.is_empty() => {
                let (line, column) = line_column(text, offset);
                return Err(XmlError {
                    line,
                    column,
                    message: format!(
                        "a second top-level element <{}>",
                        String::from_utf8_lossy(s.name().as_ref())
                    ),
                });
            }
            Event::Start(s) => {
                if stack.len() >= MAX_XML_DEPTH {
                    let (line, column) = line_column(text, offset);
                    return Err(XmlError {
                        line,
                        column,
                        message: format!("elements nested deeper than {MAX_XML_DEPTH} levels"),
                    });
                }
                let line = lines.line_at(offset);
                stack.push(start_element(&s, line, file, text, offset)?);
            }
            Event::Empty(s) => {
                let line = lines.line_at(offset);
                let element = start_element(&s, line, file, text, offset)?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(element),
                    None => root = Some(element),
                }
            }
            Event::End(_) => {
                // quick-xml checks that end tags match their start tags.
                if let Some(element) = stack.pop() {
                    match stack.last_mut() {
                        Some(parent) => parent.children.push(element),
                        None => root = Some(element),
                    }
                }
            }
            Event::Text(t) => {
                if let Some(top) = stack.last_mut() {
                    top.text
                        .push_str(&t.decode().map_err(|e| encoding(text, offset, &e))?);
                }
            }
            Event::CData(t) => {
                if let Some(top) = stack.last_mut() {
                    top.text
                        .push_str(&t.decode().map_err(|e| encoding(text, offset, &e))?);
                }
            }
            Event::GeneralRef(r) => {
                if let Some(top) = stack.last_mut() {
                    match r.resolve_char_ref().ok().flatten() {
                        Some(c) => top.text.push(c),
                        None => match r.decode().as_deref() {
                            Ok("lt") => top.text.push('<'),
                            Ok("gt") => top.text.push('>'),
                            Ok("amp") => top.text.push('&'),
                            Ok("apos") => top.text.push('\''),
                            Ok("quot") => top.text.push('"'),
                            // An entity of a DTD, or an invalid character reference: kept as
                            // written (the readers find it is not a number or a name).
                            _ => {
                                top.text.push('&');
                                top.text.push_str(&String::from_utf8_lossy(&r));
                                top.text.push(';');
                            }
                        },
                    }
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if let Some(open) = stack.last() {
        return Err(XmlError {
            line: open.line,
            column: 1,
            message: format!("<{}> is never closed", open.name),
        });
    }
    root.ok_or_else(|| XmlError {
        line: 1,
        column: 1,
        message: "no root element".to_string(),
    })
}

/// The name of the document's first element, when it can be read (to tell XML formats apart).
pub(crate) fn root_name(text: &str) -> Option<String> {
    let mut reader = quick_xml::Reader::from_str(text);
    loop {
        match reader.read_event().ok()? {
            Event::Start(s) | Event::Empty(s) => {
                return Some(String::from_utf8_lossy(s.name().as_ref()).into_owned());
            }
            Event::Eof => return None,
            _ => {}
        }
    }
}

/// Drops a tree without recursion (a deep tree's default drop would recurse once per level).
pub(crate) fn drop_flat(root: Element) {
    let mut pending = vec![root];
    while let Some(mut element) = pending.pop() {
        pending.append(&mut element.children);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_attributes_and_lines() {
        let root = parse(
            "<?xml version=\"1.0\"?>\n<a x=\"1 &amp; 2\">\n  <b/>\n  <!-- c -->\n  <c y='3'><d/></c>\n</a>",
            7,
        )
        .unwrap();
        assert_eq!(root.name, "a");
        assert_eq!(root.attr("x"), Some("1 & 2"));
        assert_eq!(root.line, 2);
        assert_eq!(root.file, 7);
        let names: Vec<_> = root.children.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["b", "c"]);
        assert_eq!(root.children[1].line, 5);
        assert_eq!(root.children[1].children[0].name, "d");
        let root = parse("<a> 1 &lt; 2<![CDATA[ & 3]]>&#x41;<b>x</b></a>", 0).unwrap();
        assert_eq!(root.text, " 1 < 2 & 3A");
        assert_eq!(root.children[0].text, "x");
        let root = parse("<a>&nbsp;&#xFFFFFFFF;</a>", 0).unwrap();
        assert_eq!(root.text, "&nbsp;&#xFFFFFFFF;");
        assert_eq!(
            root_name("<?xml version='1.0'?><!-- x --><mujoco/>").as_deref(),
            Some("mujoco")
        );
        assert_eq!(root_name("no xml"), None);
        let hopper =
            include_str!("../../../tests/data/reference/mjcf/models/gym_hopper/hopper.xml");
        assert_eq!(root_name(hopper).as_deref(), Some("mujoco"));
    }

    #[test]
    fn malformed_documents_name_their_line() {
        let e = parse("<a>\n<b>\n</a>", 0).unwrap_err();
        assert_eq!(e.line, 3, "{}", e.message);
        let e = parse("<a x='1' x='2'/>", 0).unwrap_err();
        assert!(e.message.contains("duplicated attribute"), "{}", e.message);
        let e = parse("<a/><b/>", 0).unwrap_err();
        assert!(e.message.contains("second top-level"), "{}", e.message);
        assert!(parse("  ", 0).unwrap_err().message.contains("no root"));
        let e = parse("<a>\n<b>", 0).unwrap_err();
        assert!(e.message.contains("never closed"), "{}", e.message);
    }

    #[test]
    fn nesting_is_limited_without_recursion() {
        let ok = "<a>".repeat(MAX_XML_DEPTH) + &"</a>".repeat(MAX_XML_DEPTH);
        drop_flat(parse(&ok, 0).unwrap());
        let deep = "<a>".repeat(20_000) + &"</a>".repeat(20_000);
        let e = parse(&deep, 0).unwrap_err();
        assert!(
            e.message.contains("nested deeper than 500"),
            "{}",
            e.message
        );
        assert_eq!(e.line, 1);
    }
}
