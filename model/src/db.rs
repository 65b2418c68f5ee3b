//! The salsa database: file inputs, the workspace input, and the queries' storage.
//!
//! The host (the server or `gudsl check`) owns a [`RootDatabase`], sets file texts and the file
//! list, and asks queries; everything derived is a tracked function, so an edit recomputes only
//! what depends on it. The model does no I/O: texts come in through the inputs.

use std::sync::{Arc, Mutex};

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

/// The database implementation, with an optional log of query executions for tests that
/// prove an edit recomputes only what it should.
#[salsa::db]
#[derive(Clone)]
pub struct RootDatabase {
    storage: salsa::Storage<Self>,
    executions: Arc<Mutex<Option<Vec<String>>>>,
}

impl Default for RootDatabase {
    fn default() -> Self {
        let executions: Arc<Mutex<Option<Vec<String>>>> = Arc::default();
        let log = executions.clone();
        let storage = salsa::Storage::new(Some(Box::new(move |event: salsa::Event| {
            if let salsa::EventKind::WillExecute { database_key } = event.kind {
                if let Some(log) = log.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
                    log.push(format!("{database_key:?}"));
                }
            }
        })));
        RootDatabase { storage, executions }
    }
}

#[salsa::db]
impl salsa::Database for RootDatabase {}

#[salsa::db]
impl Db for RootDatabase {}

impl RootDatabase {
    /// Starts recording which queries execute (for incrementality tests).
    pub fn record_executions(&self) {
        *self.executions.lock().unwrap_or_else(|e| e.into_inner()) = Some(Vec::new());
    }

    /// The queries executed since the last call, as `query_name(id)` strings.
    pub fn take_executions(&self) -> Vec<String> {
        self.executions.lock().unwrap_or_else(|e| e.into_inner()).as_mut().map(std::mem::take).unwrap_or_default()
    }
}

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
