//! Pinned positions: where the user put nodes (and the size they gave them), by diagram and
//! node id — the layout sidecar `<file>.gudsl.layout` beside a model file, the counterpart of
//! GMF's notation model. JSON with sorted keys and one value per line, so moving one node
//! changes one line of the file.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// The format's version, written into every file.
pub const VERSION: u32 = 1;

/// Where one node is pinned: its top-left corner, and its size where the user resized it (a
/// node is never drawn smaller than its text).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pin {
    // Declared in key order: the file's keys stay sorted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    pub x: f64,
    pub y: f64,
}

impl Pin {
    /// The size, where both sides are given.
    pub fn size(&self) -> Option<(f64, f64)> {
        self.width.zip(self.height)
    }
}

/// The pins of one diagram, by node id.
pub type Pins = BTreeMap<String, Pin>;

/// The rows of one diagram's last fresh layout: per rank that holds boxes, top to bottom (left
/// to right in a dataflow diagram), its entries in order — boxes and the long edges passing, as
/// `row_entry` writes them. A fresh layout keeps them where it can (`layout::seeded`).
pub type Rows = Vec<Vec<String>>;

/// The entry that marks, last in a row, that a wrapped drawing's column started there (with the
/// ranks without boxes before the row it started): no node or edge id has the character, and a
/// reader before it left it out as an id no longer in the graph.
pub const COLUMN_MARK: &str = "|";
/// The entry that marks, last in a row, where the row's band started along the ranks.
pub const BAND_MARK: &str = "=";

/// A row entry's text: the id, then where it was drawn — its centre across the ranks and, for a
/// box of a part laid out apart, its top — each exactly (the shortest text that reads back as
/// the same number), so that a layout from its own rows is the same layout.
pub fn row_entry(id: &str, x: Option<f64>, y: Option<f64>) -> String {
    match (x, y) {
        (Some(x), Some(y)) => format!("{id} {x} {y}"),
        (Some(x), None) => format!("{id} {x}"),
        _ => id.to_string(),
    }
}

/// A row entry read (`row_entry`): its id, and each number after it that is one (finite, below
/// 10⁷ either way; else none).
pub fn read_row_entry(text: &str) -> (&str, Option<f64>, Option<f64>) {
    let mut words = text.split(' ');
    let id = words.next().unwrap_or_default();
    let mut number = || words.next().and_then(|w| w.parse::<f64>().ok()).filter(|v| v.is_finite() && v.abs() < 1e7);
    (id, number(), number())
}

/// A layout sidecar: the pins of each diagram of one model file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayoutFile {
    #[serde(default)]
    pub diagrams: BTreeMap<String, Pins>,
    /// The rows of each diagram's last fresh layout (written with the model, read by every fresh
    /// layout after it). Declared between the others: the file's keys stay sorted.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub rows: BTreeMap<String, Rows>,
    #[serde(default = "version")]
    pub version: u32,
}

fn version() -> u32 {
    VERSION
}

impl Default for LayoutFile {
    fn default() -> LayoutFile {
        LayoutFile { diagrams: BTreeMap::new(), rows: BTreeMap::new(), version: VERSION }
    }
}

impl LayoutFile {
    /// Reads a sidecar; the error says where the text is not one.
    pub fn parse(text: &str) -> Result<LayoutFile, String> {
        let file: LayoutFile =
            serde_json::from_str(text).map_err(|e| format!("line {}, column {}: {e}", e.line(), e.column()))?;
        if file.version > VERSION {
            return Err(format!("written by a newer gudsl (layout format {}, this one reads {VERSION})", file.version));
        }
        let bad = file
            .diagrams
            .iter()
            .flat_map(|(d, pins)| pins.iter().map(move |(n, pin)| (d, n, pin)))
            .find(|(_, _, pin)| !valid(pin));
        if let Some((diagram, node, _)) = bad {
            return Err(format!("the pin of `{node}` in `{diagram}` is no position (negative, or a size not above 0)"));
        }
        Ok(file)
    }

    /// The file's text: sorted keys, two-space indentation, a final newline.
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }

    /// The pins of `diagram` (none for a diagram never arranged).
    pub fn pins(&self, diagram: &str) -> Option<&Pins> {
        self.diagrams.get(diagram).filter(|pins| !pins.is_empty())
    }

    /// The rows of `diagram`'s last fresh layout, if they were kept.
    pub fn rows(&self, diagram: &str) -> Option<&Rows> {
        self.rows.get(diagram).filter(|rows| !rows.is_empty())
    }

    /// Keeps each `(diagram, rows)` drawn as that diagram's rows; whether any changed.
    pub fn remember(&mut self, drawn: impl IntoIterator<Item = (String, Rows)>) -> bool {
        let mut changed = false;
        for (diagram, rows) in drawn {
            if self.rows.get(&diagram).map_or(!rows.is_empty(), |kept| *kept != rows) {
                changed = true;
                match rows.is_empty() {
                    true => self.rows.remove(&diagram),
                    false => self.rows.insert(diagram, rows),
                };
            }
        }
        changed
    }

    /// Whether the file holds nothing: no pin and no rows (it is then removed).
    pub fn is_empty(&self) -> bool {
        self.diagrams.is_empty() && self.rows.is_empty()
    }

    /// Keeps only the pins and row places of nodes that `exists` (diagram id, node id);
    /// diagrams left without pins or rows go.
    pub fn retain(&mut self, exists: impl Fn(&str, &str) -> bool) {
        for (diagram, pins) in &mut self.diagrams {
            pins.retain(|node, _| exists(diagram, node));
        }
        self.diagrams.retain(|_, pins| !pins.is_empty());
        for (diagram, rows) in &mut self.rows {
            rows.iter_mut().for_each(|row| row.retain(|entry| exists(diagram, read_row_entry(entry).0)));
            rows.retain(|row| !row.is_empty());
        }
        self.rows.retain(|_, rows| !rows.is_empty());
    }
}

/// Coordinates are not negative, sizes above 0, and all are finite and below a million points.
pub fn valid(pin: &Pin) -> bool {
    let coordinate = |v: f64| v.is_finite() && (0.0..1e6).contains(&v);
    let side = |v: Option<f64>| v.is_none_or(|v| v.is_finite() && v > 0.0 && v < 1e6);
    coordinate(pin.x) && coordinate(pin.y) && side(pin.width) && side(pin.height)
}

/// A coordinate as stored: to a hundredth of a point (a drag's float noise makes no diff).
pub fn rounded(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hand_written_coordinate_reads_back_unchanged_after_a_save() {
        // Found by the fuzz target `sidecar`: without exact float parsing this width drifted by
        // one ulp a save.
        let text = r#"{"diagrams": {"S": {"S.A": {"width": 120.11111111110112, "height": 80, "x": 16, "y": 40}}}}"#;
        let read = LayoutFile::parse(text).unwrap();
        assert_eq!(read.diagrams["S"]["S.A"].width, Some(120.11111111110112));
        assert_eq!(LayoutFile::parse(&read.to_json()).unwrap(), read);
    }

    #[test]
    fn written_with_sorted_keys_one_value_per_line_and_read_back() {
        let mut file = LayoutFile::default();
        let pins = file.diagrams.entry("Shapes".into()).or_default();
        pins.insert("Shapes.Square".into(), Pin { x: 40.0, y: 300.5, width: Some(200.0), height: Some(90.0) });
        pins.insert("Shapes.Circle".into(), Pin { x: 120.25, y: 40.0, width: None, height: None });
        let text = file.to_json();
        assert_eq!(
            text,
            r#"{
  "diagrams": {
    "Shapes": {
      "Shapes.Circle": {
        "x": 120.25,
        "y": 40.0
      },
      "Shapes.Square": {
        "height": 90.0,
        "width": 200.0,
        "x": 40.0,
        "y": 300.5
      }
    }
  },
  "version": 1
}
"#
        );
        assert_eq!(LayoutFile::parse(&text), Ok(file));
    }

    #[test]
    fn bad_files_are_refused_with_where_and_why() {
        let error = LayoutFile::parse("{\n  \"diagrams\": {\n    \"A\": 3\n  }\n}").unwrap_err();
        assert!(error.starts_with("line 3, column"), "{error}");
        let error = LayoutFile::parse(r#"{"diagrams": {"A": {"A.B": {"x": -5, "y": 0}}}}"#).unwrap_err();
        assert!(error.contains("`A.B` in `A`"), "{error}");
        let error = LayoutFile::parse(r#"{"diagrams": {}, "version": 7}"#).unwrap_err();
        assert!(error.contains("newer gudsl"), "{error}");
        // Unknown keys (a newer writer's extras) are no error; an empty file has no pins.
        let file = LayoutFile::parse(r#"{"diagrams": {"A": {"A.B": {"x": 1, "y": 2, "z": 3}}}, "note": 1}"#).unwrap();
        assert_eq!(file.pins("A").map(|p| p.len()), Some(1));
        assert_eq!(LayoutFile::parse("{}").unwrap().pins("A"), None);
    }

    #[test]
    fn retain_drops_the_pins_of_nodes_gone_and_their_emptied_diagrams() {
        let pin = Pin { x: 1.0, y: 2.0, width: None, height: None };
        let mut file = LayoutFile::default();
        file.diagrams.entry("A".into()).or_default().insert("A.kept".into(), pin);
        file.diagrams.entry("A".into()).or_default().insert("A.gone".into(), pin);
        file.diagrams.entry("B".into()).or_default().insert("B.gone".into(), pin);
        file.rows.insert("A".into(), vec![vec!["A.gone".into()], vec!["A.gone".into(), "A.kept".into()]]);
        file.rows.insert("B".into(), vec![vec!["B.gone".into()]]);
        file.retain(|_, node| node.ends_with("kept"));
        assert_eq!(file.diagrams.len(), 1);
        assert_eq!(file.diagrams["A"].keys().collect::<Vec<_>>(), ["A.kept"]);
        assert_eq!(file.rows.keys().collect::<Vec<_>>(), ["A"]);
        assert_eq!(file.rows["A"], [["A.kept"]]);
        file.retain(|_, _| false);
        assert!(file.is_empty());
    }
}
