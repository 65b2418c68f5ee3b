//! `SyntaxKind`: the one list of token and node kinds shared by the lexer, parser and rowan tree.

/// Declares `SyntaxKind` and `ALL_KINDS` (every variant in order, so a raw `u16` maps back
/// without `unsafe`) from one list.
macro_rules! syntax_kinds {
    ($($(#[$meta:meta])* $name:ident,)*) => {
        /// Every kind of token and node in a GU-DSL syntax tree.
        ///
        /// Tokens come first (trivia, literals, punctuation, keywords), then composite nodes.
        /// Contextual keywords (`swimlane`, `source`, `provider`, …) are lexed as [`SyntaxKind::IDENT`]
        /// and remapped by the parser where the grammar expects them.
        #[allow(non_camel_case_types, clippy::upper_case_acronyms)]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        #[repr(u16)]
        pub enum SyntaxKind {
            $($(#[$meta])* $name,)*
            #[doc(hidden)]
            __LAST,
        }

        const ALL_KINDS: &[SyntaxKind] = &[$(SyntaxKind::$name,)*];
    };
}

syntax_kinds! {
    // --- trivia and special tokens
    WHITESPACE,
    LINE_COMMENT,
    BLOCK_COMMENT,
    /// A character that starts no token.
    UNKNOWN,
    EOF,

    // --- literals and names
    IDENT,
    INT_NUMBER,
    FLOAT_NUMBER,
    STRING,
    CHAR,

    // --- punctuation
    SEMICOLON,
    COMMA,
    DOT,
    DOT2,
    COLON,
    COLON2,
    L_PAREN,
    R_PAREN,
    L_CURLY,
    R_CURLY,
    L_BRACK,
    R_BRACK,
    L_ANGLE,
    R_ANGLE,
    EQ,
    EQ2,
    BANG,
    NEQ,
    LTEQ,
    /// `>=`: composed by the parser from `>` `=`.
    GTEQ,
    PLUS,
    MINUS,
    STAR,
    SLASH,
    PERCENT,
    AMP,
    AMP2,
    PIPE,
    PIPE2,
    CARET,
    TILDE,
    QUESTION,
    /// `=>`: a transition.
    FAT_ARROW,
    /// `==>`: a connection or binding.
    LONG_FAT_ARROW,
    PLUSEQ,
    MINUSEQ,
    STAREQ,
    SLASHEQ,
    PERCENTEQ,
    AMPEQ,
    PIPEEQ,
    CARETEQ,
    SHL,
    SHLEQ,
    /// `>>`: composed by the parser from two `>`.
    SHR,
    /// `>>=`: composed by the parser from `>` `>` `=`.
    SHREQ,
    PLUS2,
    MINUS2,

    // --- reserved keywords
    ABSTRACT_KW,
    AS_KW,
    ATTRIBUTE_KW,
    BREAK_KW,
    CALL_KW,
    CASE_KW,
    CLASS_KW,
    CONST_KW,
    CONTINUE_KW,
    DEFAULT_KW,
    DO_KW,
    ELSE_KW,
    ENUM_KW,
    EXTENDS_KW,
    FALSE_KW,
    FOR_KW,
    IF_KW,
    IMPLEMENTS_KW,
    IMPORT_KW,
    INTERFACE_KW,
    LOOP_KW,
    NEW_KW,
    NULL_KW,
    PRIVATE_KW,
    PROTECTED_KW,
    PUBLIC_KW,
    REF_KW,
    RETURN_KW,
    SWITCH_KW,
    THIS_KW,
    TRUE_KW,
    UNSIGNED_KW,
    VAR_KW,
    // built-in type keywords
    BOOL_KW,
    BYTE_KW,
    CHAR_KW,
    DOUBLE_KW,
    FLOAT_KW,
    INT_KW,
    LONG_KW,
    REAL_KW,
    SHORT_KW,
    STRING_KW,
    VOID_KW,

    // --- contextual keywords (lexed as IDENT, remapped by the parser)
    CLASS_DIAGRAM_KW,
    ACTIVITY_DIAGRAM_KW,
    COMPONENT_DIAGRAM_KW,
    COMPONENT_INSTANCE_DIAGRAM_KW,
    SOURCE_KW,
    FILTER_KW,
    SINK_KW,
    PROVIDER_KW,
    PROCESSOR_KW,
    SELF_KW,
    AGGREGATION_KW,
    COMPOSITION_KW,
    GLOBAL_KW,
    SHARED_KW,
    OUT_KW,
    READ_KW,
    WRITE_KW,
    STATIC_KW,
    SWIMLANE_KW,
    OWNER_KW,
    START_KW,
    FINAL_KW,
    ACTION_KW,
    DECISION_KW,
    FORK_KW,
    JOIN_KW,
    LOOP_WINDOW_KW,
    CALC_KW,
    CALC_RANGE_KW,
    BEHAVIOR_KW,
    LOOPWINDOW2D_KW,
    LOOPWINDOW3D_KW,
    PORT_KW,
    ASYNC_KW,
    BUFFERED_KW,
    TARGET_KW,
    INSTANTIATES_KW,

    // --- nodes: structure
    SOURCE_FILE,
    /// Text the parser could not place; always accompanied by a diagnostic.
    ERROR,
    NAME,
    NAME_REF,
    PATH,
    IMPORT,
    ATTRIBUTE_LIST,
    ATTRIBUTE_USE,
    NAMED_ARG_LIST,
    NAMED_ARG,
    MODIFIERS,
    TYPE_REF,
    TYPE_ARGS,

    // --- nodes: class diagrams
    CLASS_DIAGRAM,
    CLASS,
    INTERFACE,
    ENUM,
    ENUM_VALUE,
    ATTRIBUTE_DEF,
    TEMPLATE_PARAMS,
    TEMPLATE_PARAM,
    EXTENDS_CLAUSE,
    IMPLEMENTS_CLAUSE,
    MEMBER_LIST,
    FIELD,
    METHOD,
    PARAM_LIST,
    PARAM,
    ASSOCIATION,
    MULTIPLICITY,

    // --- nodes: activity diagrams
    ACTIVITY_DIAGRAM,
    OWNER_CLAUSE,
    VARIABLE,
    SWIMLANE,
    START_NODE,
    FINAL_NODE,
    ACTION_NODE,
    DECISION_NODE,
    FORK_NODE,
    JOIN_NODE,
    LOOP_NODE,
    LOOP_WINDOW_NODE,
    CALC_NODE,
    CALC_RANGE_NODE,
    NODE_BODY,
    LOOP_HEADER,
    LOOP_SECTION,
    TRANSITION,
    GUARD,
    ARG_LIST,

    // --- nodes: statements
    BLOCK,
    VAR_DECL,
    EXPR_STMT,
    EMPTY_STMT,
    IF_STMT,
    ELSE_BRANCH,
    LOOP_STMT,
    DO_LOOP_STMT,
    FOR_STMT,
    SWITCH_STMT,
    SWITCH_CASE,
    RETURN_STMT,
    BREAK_STMT,
    CONTINUE_STMT,
    LOOP_WINDOW_STMT,
    LOOP_WINDOW_DIM,

    // --- nodes: expressions
    LITERAL,
    NAME_EXPR,
    THIS_EXPR,
    PAREN_EXPR,
    BIN_EXPR,
    PREFIX_EXPR,
    POSTFIX_EXPR,
    TERNARY_EXPR,
    CAST_EXPR,
    AS_EXPR,
    CALL_EXPR,
    INDEX_EXPR,
    MEMBER_EXPR,
    SCOPE_EXPR,
    NEW_EXPR,
    CALL_BEHAVIOR_EXPR,
    CALL_METHOD_EXPR,
    CALL_INTERFACE_EXPR,

    // --- nodes: component and component-instance diagrams
    COMPONENT_DIAGRAM,
    COMPONENT,
    PORT,
    CONNECTOR,
    CONNECTION,
    COMPONENT_INSTANCE_DIAGRAM,
    COMPONENT_INSTANCE,
    PORT_INSTANCE,
    CID_CONNECTOR,
    BINDING,

}

use SyntaxKind::*;

impl SyntaxKind {
    /// Whitespace and comments: kept in the tree, skipped by the parser.
    pub fn is_trivia(self) -> bool {
        matches!(self, WHITESPACE | LINE_COMMENT | BLOCK_COMMENT)
    }

    /// Reserved or contextual keyword.
    pub fn is_keyword(self) -> bool {
        (ABSTRACT_KW as u16..=INSTANTIATES_KW as u16).contains(&(self as u16))
    }

    /// Contextual keyword: a name everywhere the grammar does not expect it as a keyword.
    pub fn is_contextual_keyword(self) -> bool {
        (CLASS_DIAGRAM_KW as u16..=INSTANTIATES_KW as u16).contains(&(self as u16))
    }

    /// Built-in type keyword (`int`, `float`, …).
    pub fn is_builtin_type(self) -> bool {
        (BOOL_KW as u16..=VOID_KW as u16).contains(&(self as u16))
    }

    /// Leaf kind (token) rather than a node.
    pub fn is_token(self) -> bool {
        (self as u16) < SOURCE_FILE as u16
    }

    /// The reserved keyword spelled `text`, if any.
    pub fn from_keyword(text: &str) -> Option<SyntaxKind> {
        Some(match text {
            "abstract" => ABSTRACT_KW,
            "as" => AS_KW,
            "attribute" => ATTRIBUTE_KW,
            "break" => BREAK_KW,
            "call" => CALL_KW,
            "case" => CASE_KW,
            "class" => CLASS_KW,
            "const" => CONST_KW,
            "continue" => CONTINUE_KW,
            "default" => DEFAULT_KW,
            "do" => DO_KW,
            "else" => ELSE_KW,
            "enum" => ENUM_KW,
            "extends" => EXTENDS_KW,
            "false" => FALSE_KW,
            "for" => FOR_KW,
            "if" => IF_KW,
            "implements" => IMPLEMENTS_KW,
            "import" => IMPORT_KW,
            "interface" => INTERFACE_KW,
            "loop" => LOOP_KW,
            "new" => NEW_KW,
            "null" => NULL_KW,
            "private" => PRIVATE_KW,
            "protected" => PROTECTED_KW,
            "public" => PUBLIC_KW,
            "ref" => REF_KW,
            "return" => RETURN_KW,
            "switch" => SWITCH_KW,
            "this" => THIS_KW,
            "true" => TRUE_KW,
            "unsigned" => UNSIGNED_KW,
            "var" => VAR_KW,
            "bool" => BOOL_KW,
            "byte" => BYTE_KW,
            "char" => CHAR_KW,
            "double" => DOUBLE_KW,
            "float" => FLOAT_KW,
            "int" => INT_KW,
            "long" => LONG_KW,
            "real" => REAL_KW,
            "short" => SHORT_KW,
            "string" => STRING_KW,
            "void" => VOID_KW,
            _ => return None,
        })
    }

    /// The contextual keyword spelled `text`, if any.
    pub fn from_contextual_keyword(text: &str) -> Option<SyntaxKind> {
        Some(match text {
            "ClassDiagram" => CLASS_DIAGRAM_KW,
            "ActivityDiagram" => ACTIVITY_DIAGRAM_KW,
            "ComponentDiagram" => COMPONENT_DIAGRAM_KW,
            "ComponentInstanceDiagram" => COMPONENT_INSTANCE_DIAGRAM_KW,
            "source" => SOURCE_KW,
            "filter" => FILTER_KW,
            "sink" => SINK_KW,
            "provider" => PROVIDER_KW,
            "processor" => PROCESSOR_KW,
            "self" => SELF_KW,
            "aggregation" => AGGREGATION_KW,
            "composition" => COMPOSITION_KW,
            "global" => GLOBAL_KW,
            "shared" => SHARED_KW,
            "out" => OUT_KW,
            "read" => READ_KW,
            "write" => WRITE_KW,
            "static" => STATIC_KW,
            "swimlane" => SWIMLANE_KW,
            "owner" => OWNER_KW,
            "start" => START_KW,
            "final" => FINAL_KW,
            "action" => ACTION_KW,
            "decision" => DECISION_KW,
            "fork" => FORK_KW,
            "join" => JOIN_KW,
            "loopWindow" => LOOP_WINDOW_KW,
            "calc" => CALC_KW,
            "calcRange" => CALC_RANGE_KW,
            "behavior" => BEHAVIOR_KW,
            "loopwindow2D" => LOOPWINDOW2D_KW,
            "loopwindow3D" => LOOPWINDOW3D_KW,
            "port" => PORT_KW,
            "async" => ASYNC_KW,
            "buffered" => BUFFERED_KW,
            "target" => TARGET_KW,
            "instantiates" => INSTANTIATES_KW,
            _ => return None,
        })
    }

    /// How the kind reads in a diagnostic: `` `;` ``, `identifier`, `` `class` ``.
    pub fn describe(self) -> &'static str {
        match self {
            WHITESPACE => "whitespace",
            LINE_COMMENT | BLOCK_COMMENT => "comment",
            UNKNOWN => "unknown character",
            EOF => "end of file",
            IDENT => "identifier",
            INT_NUMBER => "integer",
            FLOAT_NUMBER => "number",
            STRING => "string",
            CHAR => "character literal",
            SEMICOLON => "`;`",
            COMMA => "`,`",
            DOT => "`.`",
            DOT2 => "`..`",
            COLON => "`:`",
            COLON2 => "`::`",
            L_PAREN => "`(`",
            R_PAREN => "`)`",
            L_CURLY => "`{`",
            R_CURLY => "`}`",
            L_BRACK => "`[`",
            R_BRACK => "`]`",
            L_ANGLE => "`<`",
            R_ANGLE => "`>`",
            EQ => "`=`",
            EQ2 => "`==`",
            BANG => "`!`",
            NEQ => "`!=`",
            LTEQ => "`<=`",
            GTEQ => "`>=`",
            PLUS => "`+`",
            MINUS => "`-`",
            STAR => "`*`",
            SLASH => "`/`",
            PERCENT => "`%`",
            AMP => "`&`",
            AMP2 => "`&&`",
            PIPE => "`|`",
            PIPE2 => "`||`",
            CARET => "`^`",
            TILDE => "`~`",
            QUESTION => "`?`",
            FAT_ARROW => "`=>`",
            LONG_FAT_ARROW => "`==>`",
            PLUSEQ => "`+=`",
            MINUSEQ => "`-=`",
            STAREQ => "`*=`",
            SLASHEQ => "`/=`",
            PERCENTEQ => "`%=`",
            AMPEQ => "`&=`",
            PIPEEQ => "`|=`",
            CARETEQ => "`^=`",
            SHL => "`<<`",
            SHLEQ => "`<<=`",
            SHR => "`>>`",
            SHREQ => "`>>=`",
            PLUS2 => "`++`",
            MINUS2 => "`--`",
            _ if self.is_keyword() => KEYWORD_TEXT[(self as u16 - ABSTRACT_KW as u16) as usize],
            _ => "syntax",
        }
    }

    /// Kind of a raw `u16`, if it names one.
    pub fn from_raw(raw: u16) -> Option<SyntaxKind> {
        if raw < __LAST as u16 {
            // Every value below __LAST is a variant; the table lists them in order.
            Some(ALL_KINDS[raw as usize])
        } else {
            None
        }
    }
}

/// Keyword spellings in backticks, in declaration order of the `*_KW` variants.
const KEYWORD_TEXT: &[&str] = &[
    "`abstract`",
    "`as`",
    "`attribute`",
    "`break`",
    "`call`",
    "`case`",
    "`class`",
    "`const`",
    "`continue`",
    "`default`",
    "`do`",
    "`else`",
    "`enum`",
    "`extends`",
    "`false`",
    "`for`",
    "`if`",
    "`implements`",
    "`import`",
    "`interface`",
    "`loop`",
    "`new`",
    "`null`",
    "`private`",
    "`protected`",
    "`public`",
    "`ref`",
    "`return`",
    "`switch`",
    "`this`",
    "`true`",
    "`unsigned`",
    "`var`",
    "`bool`",
    "`byte`",
    "`char`",
    "`double`",
    "`float`",
    "`int`",
    "`long`",
    "`real`",
    "`short`",
    "`string`",
    "`void`",
    "`ClassDiagram`",
    "`ActivityDiagram`",
    "`ComponentDiagram`",
    "`ComponentInstanceDiagram`",
    "`source`",
    "`filter`",
    "`sink`",
    "`provider`",
    "`processor`",
    "`self`",
    "`aggregation`",
    "`composition`",
    "`global`",
    "`shared`",
    "`out`",
    "`read`",
    "`write`",
    "`static`",
    "`swimlane`",
    "`owner`",
    "`start`",
    "`final`",
    "`action`",
    "`decision`",
    "`fork`",
    "`join`",
    "`loopWindow`",
    "`calc`",
    "`calcRange`",
    "`behavior`",
    "`loopwindow2D`",
    "`loopwindow3D`",
    "`port`",
    "`async`",
    "`buffered`",
    "`target`",
    "`instantiates`",
];

impl From<SyntaxKind> for rowan::SyntaxKind {
    fn from(kind: SyntaxKind) -> Self {
        rowan::SyntaxKind(kind as u16)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyword_table_matches_variants() {
        assert_eq!(KEYWORD_TEXT.len(), (INSTANTIATES_KW as u16 - ABSTRACT_KW as u16 + 1) as usize);
        for (i, text) in KEYWORD_TEXT.iter().enumerate() {
            let kind = SyntaxKind::from_raw(ABSTRACT_KW as u16 + i as u16).unwrap();
            let word = text.trim_matches('`');
            let back = SyntaxKind::from_keyword(word).or_else(|| SyntaxKind::from_contextual_keyword(word));
            assert_eq!(back, Some(kind), "{word}");
        }
    }

    #[test]
    fn raw_round_trip() {
        for raw in 0..__LAST as u16 {
            assert_eq!(SyntaxKind::from_raw(raw).unwrap() as u16, raw);
        }
    }
}
