//! The salsa database: file inputs, the workspace input, and the queries' storage.
//!
//! The host (the server or `gudsl check`) owns a [`RootDatabase`], sets file texts and the file
//! list, and asks queries; everything derived is a tracked function, so an edit recomputes only
//! what depends on it. The model does no I/O: texts come in through the inputs.

use std::sync::{Arc, Mutex};

use salsa::Durability;

/// One document: its path (for messages and identity) and its text.
#[salsa::input(debug)]
pub struct SourceFile {
    #[returns(ref)]
    pub path: String,
    #[returns(ref)]
    pub text: String,
}

/// The set of documents analysed together.
#[salsa::input(debug)]
pub struct Workspace {
    #[returns(ref)]
    pub files: Vec<SourceFile>,
}

/// The database trait the queries are written against.
#[salsa::db]
pub trait Db: salsa::Database {}

/// How long a file's text is expected to stay as it is (salsa durability): a text read from
/// disk or opened in the editor is [`UNEDITED`], one the user has typed into is [`EDITED`].
/// After a keystroke salsa knows at a glance that whatever reads only unedited files (their
/// parse, item tree, declarations) is unchanged, instead of verifying it query by query down
/// to each text; rust-analyzer gives library files a higher durability for the same reason.
pub const UNEDITED: Durability = Durability::MEDIUM;
/// See [`UNEDITED`].
pub const EDITED: Durability = Durability::LOW;

/// The database implementation. [`RootDatabase::with_execution_log`] builds one that logs
/// which queries execute and which memos are validated, for tests that prove an edit
/// recomputes (and re-verifies) only what it should; the default one installs no event
/// callback at all, so salsa builds no event per memo it verifies (re-checking every file of
/// the linked 200-file workspace after an edit: 19 ms without, 25 ms with the logging
/// callback).
#[salsa::db]
#[derive(Clone, Default)]
pub struct RootDatabase {
    storage: salsa::Storage<Self>,
    log: Option<Arc<Mutex<QueryLog>>>,
}

/// What [`RootDatabase::with_execution_log`] records, as `query_name(id)` strings.
#[derive(Default)]
struct QueryLog {
    executed: Vec<String>,
    validated: Vec<String>,
}

impl RootDatabase {
    /// A database that records which queries execute ([`RootDatabase::take_executions`]) and
    /// which memos are validated without executing ([`RootDatabase::take_validations`]).
    pub fn with_execution_log() -> RootDatabase {
        let log: Arc<Mutex<QueryLog>> = Arc::default();
        let writer = log.clone();
        let storage = salsa::Storage::new(Some(Box::new(move |event: salsa::Event| {
            let mut log = writer.lock().unwrap_or_else(|e| e.into_inner());
            match event.kind {
                salsa::EventKind::WillExecute { database_key } => log.executed.push(format!("{database_key:?}")),
                salsa::EventKind::DidValidateMemoizedValue { database_key } => {
                    log.validated.push(format!("{database_key:?}"))
                }
                _ => {}
            }
        })));
        RootDatabase { storage, log: Some(log) }
    }

    /// The queries executed since the last call (none for a database built without the log).
    pub fn take_executions(&self) -> Vec<String> {
        self.take(|log| &mut log.executed)
    }

    /// The memos validated (found still right, shallowly or by their inputs) since the last
    /// call.
    pub fn take_validations(&self) -> Vec<String> {
        self.take(|log| &mut log.validated)
    }

    fn take(&self, part: impl FnOnce(&mut QueryLog) -> &mut Vec<String>) -> Vec<String> {
        self.log
            .as_ref()
            .map(|log| std::mem::take(part(&mut log.lock().unwrap_or_else(|e| e.into_inner()))))
            .unwrap_or_default()
    }
}

#[salsa::db]
impl salsa::Database for RootDatabase {}

#[salsa::db]
impl Db for RootDatabase {}

/// The parse of a file (syntax tree and syntax errors).
#[salsa::tracked(returns(ref))]
pub fn parse(db: &dyn Db, file: SourceFile) -> crate::Parse {
    crate::parse(file.text(db))
}

/// The line index of a file, for converting positions at the editor boundary.
#[salsa::tracked(returns(ref))]
pub fn line_index(db: &dyn Db, file: SourceFile) -> crate::text::LineIndex {
    crate::text::LineIndex::new(file.text(db))
}
