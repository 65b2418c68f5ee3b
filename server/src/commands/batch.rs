//! Many recordings, `gudsl run MODEL --inputs PATTERN`: the recordings a run goes over (a
//! glob, or `@FILE`, a manifest of one path a line), each an independent job whose path
//! replaces `{recording}` in the values of `--set` and `--sweep`, into a folder of its own
//! named after it; the share of them one process runs (`--shard K/N`, else a Kubernetes
//! Indexed Job's or a Slurm array's index and count); and which are done already
//! (`--resume`: every run of the recording wrote a `report.json` saying it ended well — it is
//! written after every other file of the run).

use std::{
    collections::HashMap,
    path::{Path, PathBuf},
};

use gudsl_host::pipeline::StudyRow;

use super::settings::Setting;

/// What a value names to be replaced by each recording's path.
pub const PLACEHOLDER: &str = "{recording}";

/// One recording: a file or a folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Recording {
    /// Its output folder's name: the file's name without its extension, or the folder's.
    pub name: String,
    /// Absolute, as the values of the model take it.
    pub path: PathBuf,
}

/// The recordings `pattern` names — a glob relative to the current folder, or `@FILE` listing
/// one path (or glob) a line, `#` starting a comment — sorted by path, each once; refused when
/// none match or two would share an output folder.
pub fn recordings(pattern: &str) -> Result<Vec<Recording>, String> {
    let patterns: Vec<String> = match pattern.strip_prefix('@') {
        Some(manifest) => std::fs::read_to_string(manifest)
            .map_err(|e| format!("cannot read the manifest {manifest}: {e}"))?
            .lines()
            .map(|line| line.split('#').next().unwrap_or("").trim().to_string())
            .filter(|line| !line.is_empty())
            .collect(),
        None => vec![pattern.to_string()],
    };
    let current = std::env::current_dir().map_err(|e| format!("no current folder: {e}"))?;
    let mut paths = Vec::new();
    for pattern in &patterns {
        let matches = glob::glob(pattern).map_err(|e| format!("`{pattern}` is no pattern: {e}"))?;
        let before = paths.len();
        for path in matches {
            paths.push(gudsl_files::lexical(&current.join(path.map_err(|e| e.to_string())?)));
        }
        if paths.len() == before {
            return Err(format!("`{pattern}` names no recording (relative to {})", current.display()));
        }
    }
    paths.sort();
    paths.dedup();
    let mut named: HashMap<String, PathBuf> = HashMap::new();
    let mut out = Vec::new();
    for path in paths {
        let name = name_of(&path);
        if let Some(other) = named.insert(name.clone(), path.clone()) {
            return Err(format!(
                "{} and {} would both write into `{name}`: give recordings distinct names",
                other.display(),
                path.display()
            ));
        }
        out.push(Recording { name, path });
    }
    Ok(out)
}

fn name_of(path: &Path) -> String {
    let name = if path.is_dir() { path.file_name() } else { path.file_stem() };
    name.map_or_else(|| "recording".to_string(), |n| n.to_string_lossy().into_owned())
}

/// Shard `index` (from 0) of `count`: every `count`-th recording from the `index`-th.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

/// Reads `--shard K/N` (K from 0 to N − 1).
pub fn shard(text: &str) -> Result<Shard, String> {
    let (index, count) = text.split_once('/').ok_or("expected K/N, e.g. 0/4 (K from 0 to N - 1)")?;
    let number = |s: &str| s.trim().parse::<usize>().map_err(|_| format!("`{s}` is no whole number"));
    let (index, count) = (number(index)?, number(count)?);
    if count == 0 || index >= count {
        return Err(format!("shard {index} of {count}: K runs from 0 to N - 1"));
    }
    Ok(Shard { index, count })
}

/// The shard the scheduler gives through the environment (`var` reads it): a Kubernetes
/// Indexed Job's `JOB_COMPLETION_INDEX` with `JOB_COMPLETION_COUNT` (set it to the Job's
/// `completions`), or a Slurm array's `SLURM_ARRAY_TASK_ID` (less `SLURM_ARRAY_TASK_MIN`) with
/// `SLURM_ARRAY_TASK_COUNT`; `None` where neither is set.
pub fn shard_from_env(var: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>, String> {
    let read = |name: &str| -> Result<Option<usize>, String> {
        var(name).map(|v| v.trim().parse().map_err(|_| format!("{name}={v} is no whole number"))).transpose()
    };
    if let Some(index) = read("JOB_COMPLETION_INDEX")? {
        let count = read("JOB_COMPLETION_COUNT")?
            .ok_or("JOB_COMPLETION_INDEX is set but JOB_COMPLETION_COUNT is not: set it to the Job's completions")?;
        return shard(&format!("{index}/{count}")).map(Some);
    }
    if let Some(task) = read("SLURM_ARRAY_TASK_ID")? {
        let count =
            read("SLURM_ARRAY_TASK_COUNT")?.ok_or("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not")?;
        let first = read("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let index = task.checked_sub(first).ok_or("SLURM_ARRAY_TASK_ID is below SLURM_ARRAY_TASK_MIN")?;
        return shard(&format!("{index}/{count}")).map(Some);
    }
    Ok(None)
}

/// The recordings of `shard` (all without one): the k-th of the sorted list where
/// k mod N = K, so every recording is run by exactly one shard.
pub fn mine(recordings: Vec<Recording>, shard: Option<Shard>) -> Vec<Recording> {
    let Some(shard) = shard else { return recordings };
    recordings.into_iter().enumerate().filter(|(k, _)| k % shard.count == shard.index).map(|(_, r)| r).collect()
}

/// `setting` for `recording`: `{recording}` replaced by its path in every value, the
/// recording first in what the run reports it ran with.
pub fn with_recording(setting: &Setting, recording: &Recording) -> Setting {
    let path = recording.path.to_string_lossy();
    let mut setting = setting.clone();
    for assignment in &mut setting.assignments {
        assignment.value = assignment.value.replace(PLACEHOLDER, &path);
    }
    setting
}

/// Whether any value of `setting` names `{recording}`.
pub fn names_recording(setting: &Setting) -> bool {
    setting.assignments.iter().any(|a| a.value.contains(PLACEHOLDER))
}

/// The folder (relative to the output folder, `/`-separated) of the run of `setting` on
/// `recording`: the recording's name, then the setting's in a study.
pub fn folder(recording: Option<&Recording>, setting: &Setting, study: bool) -> String {
    let parts = [recording.map(|r| r.name.clone()), study.then(|| setting.folder())];
    parts.into_iter().flatten().collect::<Vec<_>>().join("/")
}

/// Whether the runs of `recording` are done: each setting's folder holds a `report.json`
/// (of `reports`, by folder) saying the run ended well.
pub fn done(reports: &HashMap<String, StudyRow>, recording: &Recording, settings: &[Setting], study: bool) -> bool {
    settings.iter().all(|s| reports.get(&folder(Some(recording), s, study)).is_some_and(|row| row.state == "ok"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| vars.iter().find(|(n, _)| *n == name).map(|(_, v)| v.to_string())
    }

    #[test]
    fn shards_come_from_the_flag_or_the_scheduler() {
        assert_eq!(shard("1/4"), Ok(Shard { index: 1, count: 4 }));
        assert!(shard("4/4").unwrap_err().contains("from 0 to N - 1"));
        assert!(shard("x/4").is_err() && shard("1").is_err() && shard("0/0").is_err());
        assert_eq!(shard_from_env(env(&[])), Ok(None));
        let kubernetes = [("JOB_COMPLETION_INDEX", "2"), ("JOB_COMPLETION_COUNT", "5")];
        assert_eq!(shard_from_env(env(&kubernetes)), Ok(Some(Shard { index: 2, count: 5 })));
        assert!(shard_from_env(env(&[("JOB_COMPLETION_INDEX", "2")])).unwrap_err().contains("JOB_COMPLETION_COUNT"));
        let slurm = [("SLURM_ARRAY_TASK_ID", "3"), ("SLURM_ARRAY_TASK_COUNT", "3"), ("SLURM_ARRAY_TASK_MIN", "1")];
        assert_eq!(shard_from_env(env(&slurm)), Ok(Some(Shard { index: 2, count: 3 })), "an array 1-3");
    }

    #[test]
    fn every_recording_is_in_exactly_one_shard() {
        let all: Vec<Recording> =
            (0..11).map(|k| Recording { name: format!("r{k:02}"), path: PathBuf::from(format!("/r{k:02}")) }).collect();
        let mut union: Vec<Recording> =
            (0..4).flat_map(|index| mine(all.clone(), Some(Shard { index, count: 4 }))).collect();
        union.sort_by(|a, b| a.path.cmp(&b.path));
        assert_eq!(union, all);
        assert_eq!(mine(all.clone(), Some(Shard { index: 3, count: 4 })).len(), 2);
    }
}
