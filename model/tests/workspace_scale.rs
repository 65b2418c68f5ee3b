//! Incrementality at workspace scale: the declaration edits of `tests/lsp/bench.py linked` in
//! the densely linked 200-file workspace (`synth::linked_workspace`), counted query by query.
//! A field's type becoming unknown and a class renamed must re-run the per-file queries of the
//! edited file only, re-read only the edited namespace, rebuild no workspace-wide map, and
//! re-check exactly the files that use the changed class.

use std::collections::{BTreeMap, BTreeSet};

use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace, EDITED, UNEDITED},
    hir::file_diagnostics,
    ide::find_references,
};
use salsa::Setter;

struct Linked {
    db: RootDatabase,
    workspace: Workspace,
    files: Vec<SourceFile>,
}

impl Linked {
    fn new(files: usize) -> Linked {
        let db = RootDatabase::with_execution_log();
        let files: Vec<SourceFile> = gudsl_model::synth::linked_workspace(files)
            .into_iter()
            .map(|f| SourceFile::builder(f.path, f.text).durability(UNEDITED).new(&db))
            .collect();
        // The bundled library first, as every workspace has it: the counts below prove that
        // no edit re-checks it.
        let library = gudsl_model::library::library_files(&db);
        let workspace = Workspace::new(&db, library.into_iter().chain(files.iter().copied()).collect());
        Linked { db, workspace, files }
    }

    /// Replaces the first `from` in the edited file (f001) by `to`, as a keystroke does
    /// (`AnalysisHost::edit_file`: the text becomes `EDITED`).
    fn edit(&mut self, from: &str, to: &str) {
        let edited = self.files[1];
        let text = edited.text(&self.db).replacen(from, to, 1);
        assert_ne!(&text, edited.text(&self.db), "`{from}` is not in the file");
        edited.set_text(&mut self.db).with_durability(EDITED).to(text);
    }

    /// The edited file's diagnostics (what the server publishes first), then every file's, with
    /// the queries each step executed, counted by query; and the memos the first step
    /// validated without executing them.
    fn check(&self) -> (Vec<String>, Counts, Counts) {
        self.check_validating().0
    }

    fn check_validating(&self) -> ((Vec<String>, Counts, Counts), Counts) {
        self.db.take_validations();
        let messages = file_diagnostics(&self.db, self.workspace, self.files[1]).iter().map(|d| d.message.clone());
        let messages = messages.collect();
        let edited = counts(self.db.take_executions());
        let validated = counts(self.db.take_validations());
        for &file in self.workspace.files(&self.db) {
            file_diagnostics(&self.db, self.workspace, file);
        }
        ((messages, edited, counts(self.db.take_executions())), validated)
    }

    /// The files other than f001 that write `name` as a whole word (their indexes).
    fn users_of(&self, name: &str) -> BTreeSet<usize> {
        (2..self.files.len()).filter(|&i| words(self.files[i].text(&self.db), name) > 0).collect()
    }
}

/// How often `text` writes `name` as a whole word, outside the doc comments.
fn words(text: &str, name: &str) -> usize {
    let is_word = |c: char| c.is_alphanumeric() || c == '_';
    let in_line = |line: &str| {
        line.match_indices(name)
            .filter(|(at, _)| {
                let before = line[..*at].chars().next_back();
                let after = line[at + name.len()..].chars().next();
                !before.is_some_and(is_word) && !after.is_some_and(is_word)
            })
            .count()
    };
    text.lines().filter(|line| !line.trim_start().starts_with("/**")).map(in_line).sum()
}

type Counts = BTreeMap<String, usize>;

fn counts(executions: Vec<String>) -> Counts {
    let mut counts = Counts::new();
    for execution in executions {
        *counts.entry(execution.split('(').next().unwrap_or_default().to_string()).or_default() += 1;
    }
    counts
}

fn ran(counts: &Counts, query: &str) -> usize {
    counts.get(query).copied().unwrap_or(0)
}

/// Per-file queries run for the edited file only; no query reads every file.
fn assert_local(step: &str, edited: &Counts, rest: &Counts) {
    for query in ["parse", "item_tree", "file_diagrams", "file_types", "file_type_names"] {
        assert!(ran(edited, query) <= 1, "{step}: {query} ran {} times: {edited:#?}", ran(edited, query));
        assert_eq!(ran(rest, query), 0, "{step}: {query} ran for other files: {rest:#?}");
    }
    for query in ["def_map", "namespace_files", "type_names"] {
        assert_eq!(ran(edited, query) + ran(rest, query), 0, "{step}: {query} ran: {edited:#?} {rest:#?}");
    }
    // Only the edited file's namespace `M1` is re-read.
    assert!(ran(edited, "namespace_definitions") + ran(rest, "namespace_definitions") <= 1, "{step}: {edited:#?}");
    // The lookups re-run are names of `M1`, as many as the files linked to it ask, not more.
    assert!(ran(edited, "lookup") <= 120, "{step}: {edited:#?}");
}

#[test]
fn declaration_edits_in_a_linked_workspace_recompute_only_what_they_change() {
    let mut ws = Linked::new(200);
    let (messages, _, _) = ws.check();
    assert!(messages.is_empty(), "{messages:?}");
    // A first round builds what only unresolved names ask (the index of type names); the
    // second is what every later keystroke costs.
    for round in 0..2 {
        let step = |what: &str| format!("round {round}: {what}");
        ws.edit("public String name;", "public StringX name;");
        let (messages, edited, rest) = ws.check();
        assert_eq!(messages.len(), 1, "{messages:?}");
        assert!(messages[0].contains("`StringX`"), "{messages:?}");
        if round == 1 {
            assert_local(&step("type made unknown"), &edited, &rest);
            // The index of type names is re-read only in the buckets asked after type names
            // changed: here the one of `StringX`, and that of `E1_3` (renamed back at the end
            // of the round before) if it is asked.
            assert!(ran(&edited, "type_names_in_bucket") <= 2, "{edited:#?}");
            // The class E1_0 changed (a field's type): the files that use it are re-checked.
            assert_eq!(ran(&edited, "check_file") + ran(&rest, "check_file"), 1 + ws.users_of("E1_0").len());
        }

        ws.edit("public class E1_3 ", "public class E1_3Z ");
        let ((messages, edited, rest), validated) = ws.check_validating();
        assert_eq!(messages.len(), 2, "{messages:?}");
        assert!(messages.iter().any(|m| m.contains("`E1_3`")), "{messages:?}");
        if round == 1 {
            assert_local(&step("class renamed"), &edited, &rest);
            // The other files' texts are unedited (durability): the edited file's check finds
            // their declarations unchanged without walking down to their syntax trees.
            for query in ["parse", "item_tree"] {
                assert_eq!(ran(&validated, query), 0, "{query} validated: {validated:#?}");
            }
            assert!(ran(&validated, "file_diagrams") >= 199, "{validated:#?}");
            // The buckets of `E1_3Z` (new) and `E1_3` (now unresolved), if they differ.
            assert!(ran(&edited, "type_names_in_bucket") <= 2, "{edited:#?}");
            assert_eq!(ran(&edited, "check_file") + ran(&rest, "check_file"), 1 + ws.users_of("E1_3").len());
        }

        ws.edit("public StringX name;", "public String name;");
        ws.edit("public class E1_3Z ", "public class E1_3 ");
        let (messages, edited, rest) = ws.check();
        assert!(messages.is_empty(), "{messages:?}");
        if round == 1 {
            assert_local(&step("both undone"), &edited, &rest);
            let users = ws.users_of("E1_0").union(&ws.users_of("E1_3")).count();
            assert_eq!(ran(&edited, "check_file") + ran(&rest, "check_file"), 1 + users);
        }
    }
}

#[test]
fn references_resolve_only_the_names_spelled_like_the_declaration() {
    let mut ws = Linked::new(200);
    ws.check();
    let edited = ws.files[1];
    let references = |ws: &Linked| {
        let at = ws.files[1].text(&ws.db).find("public class E1_5 ").unwrap() + "public class E".len();
        find_references(&ws.db, ws.workspace, edited, (at as u32).into(), true)
    };
    let found = references(&ws);
    let written: usize = ws.files.iter().map(|f| words(f.text(&ws.db), "E1_5")).sum();
    assert_eq!(found.len(), written, "every `E1_5` of the workspace names the class");
    assert!(found.len() > 2, "the class is used in other files: {found:?}");
    // After an edit of another file, only that file's names are read again.
    ws.db.take_executions();
    let other = ws.files[7];
    let text = other.text(&ws.db).replacen("public String name;", "public String label;", 1);
    other.set_text(&mut ws.db).to(text);
    assert_eq!(references(&ws), found);
    let ran = counts(ws.db.take_executions());
    for query in ["parse", "file_name_uses", "file_names_used", "name_index"] {
        assert!(ran.get(query).copied().unwrap_or(0) <= 1, "{query}: {ran:#?}");
    }
}
