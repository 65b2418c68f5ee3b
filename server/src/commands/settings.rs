//! `--set INSTANCE.PARAMETER=VALUE` and `--sweep INSTANCE.PARAMETER=V1,V2,…` of `gudsl run`:
//! the settings a pipeline runs with — one, or the grid of a parameter study (every
//! combination of the swept values, the first sweep changing slowest) — each written into the
//! model's text in memory by the model's own parameter edit, so a value is checked as if typed
//! (E0403) and told at the argument that gave it. Names are the model's: the instance's and its
//! component's field's.

use gudsl_model::{analysis::FileId, syntax::TextRange, AnalysisHost};

/// One parameter given a value on the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Assignment {
    pub instance: String,
    pub parameter: String,
    /// As written in the model (`7`, `0.5`, `true`, `"file.npy"`, `Scene.Sphere`).
    pub value: String,
}

impl Assignment {
    /// `Instance.parameter`.
    pub fn name(&self) -> String {
        format!("{}.{}", self.instance, self.parameter)
    }
}

/// A parameter and the values a study runs it at.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sweep {
    pub instance: String,
    pub parameter: String,
    pub values: Vec<String>,
}

/// Reads `--set`'s `INSTANCE.PARAMETER=VALUE`.
pub fn assignment(text: &str) -> Result<Assignment, String> {
    let (name, value) = text.split_once('=').ok_or("expected INSTANCE.PARAMETER=VALUE, e.g. Motion.windowSize=7")?;
    let (instance, parameter) = name.trim().split_once('.').ok_or_else(|| {
        format!(
            "`{}` names no parameter: write the instance, a dot and the parameter, e.g. Motion.windowSize",
            name.trim()
        )
    })?;
    let value = value.trim();
    if value.is_empty() {
        return Err(format!("`{}` needs a value after `=`", name.trim()));
    }
    Ok(Assignment { instance: instance.to_string(), parameter: parameter.to_string(), value: value.to_string() })
}

/// Reads `--sweep`'s `INSTANCE.PARAMETER=V1,V2,…` (a comma inside double quotes is text).
pub fn sweep(text: &str) -> Result<Sweep, String> {
    let Assignment { instance, parameter, value } = assignment(text)?;
    let values = split_values(&value);
    if let Some(empty) = values.iter().position(String::is_empty) {
        return Err(format!("value {} of `{instance}.{parameter}` is empty", empty + 1));
    }
    Ok(Sweep { instance, parameter, values })
}

/// `a,b,"c,d"` as `a`, `b`, `"c,d"`.
fn split_values(text: &str) -> Vec<String> {
    let (mut values, mut current, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        match c {
            '"' => quoted = !quoted,
            '\\' if quoted => {
                current.push(c);
                chars.next().into_iter().for_each(|next| current.push(next));
                continue;
            }
            ',' if !quoted => {
                values.push(std::mem::take(&mut current).trim().to_string());
                continue;
            }
            _ => {}
        }
        current.push(c);
    }
    values.push(current.trim().to_string());
    values
}

/// One setting of a run: every value given, and of those the swept ones.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Setting {
    pub assignments: Vec<Assignment>,
    /// `Instance.parameter` and value of each sweep, in the order swept.
    pub swept: Vec<(String, String)>,
}

impl Setting {
    /// The name of its output folder in a study: its swept values (`Motion.windowSize=7,…`).
    pub fn folder(&self) -> String {
        self.swept.iter().map(|(name, value)| format!("{name}={value}")).collect::<Vec<_>>().join(",")
    }

    /// How its values were given, for messages: `--set A.b=1 --sweep C.d=2`.
    pub fn given(&self, assignment: &Assignment) -> String {
        let flag = if self.swept.iter().any(|(name, _)| *name == assignment.name()) { "--sweep" } else { "--set" };
        format!("{flag} {}={}", assignment.name(), assignment.value)
    }
}

/// The settings to run: the grid over the sweeps (one setting without any), each with every
/// `--set`; a parameter given twice is refused.
pub fn grid(sets: &[Assignment], sweeps: &[Sweep]) -> Result<Vec<Setting>, String> {
    let mut names: Vec<String> = sets.iter().map(Assignment::name).collect();
    names.extend(sweeps.iter().map(|s| format!("{}.{}", s.instance, s.parameter)));
    for (k, name) in names.iter().enumerate() {
        if names[..k].contains(name) {
            return Err(format!("`{name}` is given more than once (by --set or --sweep)"));
        }
    }
    let mut settings = vec![Setting { assignments: sets.to_vec(), swept: Vec::new() }];
    for sweep in sweeps {
        let name = format!("{}.{}", sweep.instance, sweep.parameter);
        settings = settings
            .iter()
            .flat_map(|setting| {
                sweep.values.iter().map(|value| {
                    let mut next = setting.clone();
                    next.assignments.push(Assignment {
                        instance: sweep.instance.clone(),
                        parameter: sweep.parameter.clone(),
                        value: value.clone(),
                    });
                    next.swept.push((name.clone(), value.clone()));
                    next
                })
            })
            .collect();
    }
    Ok(settings)
}

/// Writes `setting` into the text of `file` (`original`, the model as read) in the analysis;
/// the range each assignment's value stands at in the text then, or why one cannot be written.
pub fn apply(
    host: &mut AnalysisHost,
    file: FileId,
    original: &str,
    diagram: &str,
    setting: &Setting,
) -> Result<Vec<TextRange>, String> {
    host.set_file_text(file, original.to_string());
    for assignment in &setting.assignments {
        let edit = edit(host, diagram, assignment).map_err(|why| format!("{}: {why}", setting.given(assignment)))?;
        let text = gudsl_model::text::with_edits(host.file_text(file), [(edit.range, edit.text.as_str())]);
        host.set_file_text(file, text);
    }
    // Where each value stands once all are written: an edit before it may have moved it.
    setting
        .assignments
        .iter()
        .map(|a| edit(host, diagram, a).map(|edit| edit.value).map_err(|why| format!("{}: {why}", setting.given(a))))
        .collect()
}

fn edit(host: &AnalysisHost, diagram: &str, a: &Assignment) -> Result<gudsl_model::ide::ParameterEdit, String> {
    match host.analysis().parameter_edit(diagram, &a.instance, &a.parameter, &a.value) {
        Ok(edit) => edit,
        Err(_) => Err("the analysis was cancelled".to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(text: &str) -> Assignment {
        assignment(text).unwrap()
    }

    #[test]
    fn assignments_and_sweeps_read_as_written() {
        assert_eq!(
            set(" Motion.windowSize = 7 "),
            Assignment { instance: "Motion".into(), parameter: "windowSize".into(), value: "7".into() }
        );
        assert_eq!(set("Cam.scene=Scene.Box").value, "Scene.Box", "an enum member keeps its dot");
        assert!(assignment("windowSize=7").unwrap_err().contains("names no parameter"));
        assert!(assignment("Motion.windowSize").unwrap_err().contains("INSTANCE.PARAMETER=VALUE"));
        assert!(assignment("Motion.windowSize=").unwrap_err().contains("needs a value"));
        let swept = sweep("Motion.threshold=0, 1,5").unwrap();
        assert_eq!(swept.values, ["0", "1", "5"]);
        assert_eq!(sweep(r#"Truth.groundTruth="a,b.npy","c.npy""#).unwrap().values, [r#""a,b.npy""#, r#""c.npy""#]);
        assert!(sweep("Motion.threshold=0,,1").unwrap_err().contains("value 2"));
    }

    #[test]
    fn the_grid_is_every_combination_the_first_sweep_slowest() {
        let sweeps = [sweep("M.a=1,2").unwrap(), sweep("M.b=x,y,z").unwrap()];
        let settings = grid(&[set("M.c=0")], &sweeps).unwrap();
        let folders: Vec<String> = settings.iter().map(Setting::folder).collect();
        assert_eq!(folders, ["M.a=1,M.b=x", "M.a=1,M.b=y", "M.a=1,M.b=z", "M.a=2,M.b=x", "M.a=2,M.b=y", "M.a=2,M.b=z"]);
        assert!(settings.iter().all(|s| s.assignments[0] == set("M.c=0") && s.assignments.len() == 3));
        assert_eq!(settings[4].given(&settings[4].assignments[2]), "--sweep M.b=y");
        assert_eq!(settings[4].given(&settings[4].assignments[0]), "--set M.c=0");
        assert_eq!(grid(&[], &[]).unwrap().len(), 1, "no study: one setting");
        assert!(grid(&[set("M.a=3")], &sweeps).unwrap_err().contains("`M.a` is given more than once"));
    }
}
