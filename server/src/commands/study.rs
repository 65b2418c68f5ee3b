//! A parameter study, `gudsl run --sweep`: each setting runs into a folder of its own beneath
//! the output folder (named by its swept values), one after another on the same device; then
//! the study's table on stdout and `study.csv`, `study.svg` and `study.png` at the top of the
//! output folder. Exit code: the worst of the settings' runs.

use std::process::ExitCode;

use gudsl_host::pipeline::{study_table, write_study, OutputDir, PipelineReport, PreparedPipeline, StudyRun};

use super::settings::Setting;

/// Runs each setting's prepared pipeline in turn into its folder (`run_one`: its report and
/// exit code).
pub fn run(
    settings: &[Setting],
    prepared: Vec<PreparedPipeline>,
    mut output: OutputDir,
    mut run_one: impl FnMut(PreparedPipeline, OutputDir) -> (PipelineReport, u8),
) -> ExitCode {
    let mut runs = Vec::new();
    let mut worst = 0;
    for (k, (setting, prepared)) in settings.iter().zip(prepared).enumerate() {
        let folder = setting.folder();
        eprintln!("setting {}/{}: {}", k + 1, settings.len(), folder.replace(',', " "));
        let nested = match output.nested(&folder) {
            Ok(nested) => nested,
            Err(error) => {
                eprintln!("gudsl run: {error}");
                return ExitCode::from(2);
            }
        };
        let (report, code) = run_one(prepared, nested);
        worst = worst.max(code);
        runs.push(StudyRun { setting: setting.swept.clone(), folder, report });
    }
    println!("\nstudy of {} settings", runs.len());
    print!("{}", study_table(&runs));
    if let Err(error) = write_study(&runs, &mut output) {
        eprintln!("gudsl run: {error}");
        return ExitCode::from(2);
    }
    println!("wrote study.csv, study.svg and study.png in {}", output.path().display());
    ExitCode::from(worst)
}
