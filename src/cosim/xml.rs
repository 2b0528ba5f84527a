//! A small element tree over quick-xml, enough for SSP files. Names are kept without their
//! namespace prefix: SSP files in the wild use `ssd:`, `ssc:`, `ssv:` or a default namespace,
//! and the elements we read are unambiguous by local name.

use quick_xml::events::{BytesStart, Event};

#[derive(Debug, Clone, Default)]
pub struct Element {
    pub name: String,
    pub attributes: Vec<(String, String)>,
    pub children: Vec<Element>,
    /// 1-based line of the start tag, for error messages.
    pub line: usize,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attributes.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }
    pub fn child(&self, name: &str) -> Option<&Element> {
        self.children.iter().find(|c| c.name == name)
    }
    pub fn children_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.children.iter().filter(move |c| c.name == name)
    }
    /// The children of the first child called `list` that are called `item` (e.g. Connectors/Connector).
    pub fn list<'a>(&'a self, list: &'a str, item: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.child(list).into_iter().flat_map(move |l| l.children_named(item))
    }
}

fn local_name(raw: &str) -> String {
    raw.rsplit_once(':').map_or(raw, |(_, local)| local).to_string()
}

fn line_at(text: &str, offset: usize) -> usize {
    1 + text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

fn element(start: &BytesStart, line: usize) -> Result<Element, String> {
    let mut attributes = Vec::new();
    for a in start.attributes() {
        let a = a.map_err(|e| format!("line {line}: {e}"))?;
        let key = a.key.as_ref().to_string();
        if key == "xmlns" || key.starts_with("xmlns:") {
            continue;
        }
        let value = a
            .normalized_value(quick_xml::XmlVersion::Implicit1_0)
            .map_err(|e| format!("line {line}: attribute {key}: {e}"))?
            .into_owned();
        attributes.push((local_name(&key), value));
    }
    Ok(Element {
        name: local_name(start.name().as_ref()),
        attributes,
        children: Vec::new(),
        line,
    })
}

/// Deeper nesting is refused: no SSP file needs more than a dozen levels, and a tree of millions
/// would exhaust the stack when it is dropped.
pub const MAX_DEPTH: usize = 200;

/// Parses a whole document and returns its root element.
pub fn parse(text: &str) -> Result<Element, String> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut stack: Vec<Element> = Vec::new();
    let mut root = None;
    loop {
        let pos = reader.buffer_position() as usize;
        let event = reader
            .read_event()
            .map_err(|e| format!("line {}: {e}", line_at(text, reader.error_position() as usize)))?;
        match event {
            Event::Start(s) => {
                if stack.len() == MAX_DEPTH {
                    let line = line_at(text, pos);
                    return Err(format!("line {line}: elements nested deeper than {MAX_DEPTH} levels"));
                }
                stack.push(element(&s, line_at(text, pos))?)
            }
            Event::Empty(s) => {
                let e = element(&s, line_at(text, pos))?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(e),
                    None => root = Some(e),
                }
            }
            Event::End(_) => {
                let e = stack.pop().ok_or("unbalanced end tag")?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(e),
                    None => root = Some(e),
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if !stack.is_empty() {
        return Err(format!("element <{}> is never closed", stack[stack.len() - 1].name));
    }
    root.ok_or_else(|| "no root element".into())
}
