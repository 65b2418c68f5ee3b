//! `SyntaxKind`: the one list of token and node kinds shared by the lexer, parser and rowan tree,
//! generated from `model/gudsl.ungram` (see `tests/sourcegen`), and its conversion to rowan's.

#[rustfmt::skip]
mod generated;

pub use generated::SyntaxKind;
use generated::ALL_KINDS;

impl SyntaxKind {
    /// Kind of a raw `u16`, if it names one.
    pub fn from_raw(raw: u16) -> Option<SyntaxKind> {
        ALL_KINDS.get(raw as usize).copied()
    }
}

impl From<SyntaxKind> for rowan::SyntaxKind {
    fn from(kind: SyntaxKind) -> Self {
        rowan::SyntaxKind(kind as u16)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_keyword_reads_back_from_its_spelling() {
        let keywords: Vec<SyntaxKind> = ALL_KINDS.iter().copied().filter(|k| k.is_keyword()).collect();
        assert_eq!(keywords.len(), 81);
        for kind in keywords {
            let word = kind.describe().trim_matches('`');
            let back = SyntaxKind::from_keyword(word).or_else(|| SyntaxKind::from_contextual_keyword(word));
            assert_eq!(back, Some(kind), "{word}");
            assert_eq!(SyntaxKind::from_contextual_keyword(word).is_some(), kind.is_contextual_keyword(), "{word}");
        }
    }

    #[test]
    fn raw_round_trip() {
        for raw in 0..ALL_KINDS.len() as u16 {
            assert_eq!(SyntaxKind::from_raw(raw).unwrap() as u16, raw);
        }
        assert_eq!(SyntaxKind::from_raw(ALL_KINDS.len() as u16), None);
    }
}
