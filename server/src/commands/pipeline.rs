//! `gudsl run FILE --diagram PIPELINE`: a component-instance diagram run as a ToF pipeline on
//! the first wgpu adapter (`--cpu`: the CPU reference), frame after frame with a progress bar on
//! a terminal (a line a frame otherwise), then a table of the stages — time per frame and share
//! of the total — and the files written, all under the output folder (default
//! `gudsl-out/<diagram>/`), with `report.json` beside them. A pipeline the plan finds problems
//! in (E0401–E0403) or whose files or components do not fit (E0404, E0405) is refused with its
//! diagnostics. Exit code: 0 done, 1 a problem of the model or a failed stage, 2 an input or
//! output that cannot be read or written, or no device.

use std::{collections::HashMap, io::IsTerminal, path::Path, process::ExitCode, sync::atomic::AtomicBool};

use gudsl_host::{
    diagnostics::file_diagnostics,
    pipeline::{
        self, rows_beneath, study_table, summary, table, write_report, write_study, ErrorKind, OutputDir,
        PipelineError, PipelineObserver, PipelineReport, Preparations, PreparedPipeline, StudyRow,
    },
};
use gudsl_model::{
    analysis::{Analysis, FileId},
    hir::{pipeline::PipelinePlan, DiagnosticCode, Severity},
    syntax::TextRange,
    AnalysisHost,
};
use gudsl_runtime::Gpu;

use super::{
    batch::{self, Recording, Shard},
    settings::{self, Assignment, Setting, Sweep},
};
use crate::report::{self, Finding};

/// What `run` was asked to do with a pipeline.
pub struct PipelineArgs<'a> {
    pub diagram: &'a str,
    pub frames: Option<usize>,
    pub cpu: bool,
    /// `--one-frame-at-a-time`: frames never overlap on the GPU.
    pub one_frame_at_a_time: bool,
    /// `--unfused`: every stage runs its own kernels.
    pub unfused: bool,
    pub output: Option<&'a Path>,
    /// `--set`: values every setting runs with.
    pub sets: &'a [Assignment],
    /// `--sweep`: the parameter study's grid.
    pub sweeps: &'a [Sweep],
    /// `--inputs`: the recordings, a job each.
    pub inputs: Option<&'a str>,
    /// `--shard`; unset, the scheduler's (`batch::shard_from_env`).
    pub shard: Option<Shard>,
    /// `--resume`: skip the recordings that are done.
    pub resume: bool,
}

/// One run to make: the job's recording, the setting, its folder beneath the output folder.
struct Planned {
    recording: Option<Recording>,
    setting: Setting,
    folder: String,
    prepared: PreparedPipeline,
}

/// Runs the pipeline `args` names — once, once a setting of a parameter study, for each
/// recording of `--inputs` — taking what the check of the model prepared from `preparations`.
/// Every run is checked and prepared before the first starts; a recording that cannot run
/// fails alone.
pub fn run(
    host: &mut AnalysisHost,
    files: &[FileId],
    preparations: &Preparations,
    mut checked: report::Report,
    args: &PipelineArgs,
) -> ExitCode {
    let (settings, jobs, shard) = match settings_and_jobs(args) {
        Ok(planned) => planned,
        Err(why) => {
            eprintln!("gudsl run: {why}");
            return ExitCode::from(1);
        }
    };
    let plan = match host.analysis().pipeline_plan(args.diagram) {
        Ok(Some(plan)) => plan,
        Ok(None) => {
            eprintln!("gudsl run: no component-instance diagram `{}`", args.diagram);
            return ExitCode::from(1);
        }
        Err(_) => return cancelled(),
    };
    let Some(file) = files.iter().position(|f| *f == plan.file) else {
        eprintln!("gudsl run: `{}` is not in the files given", plan.diagram);
        return ExitCode::from(1);
    };
    if !plan.diagnostics.is_empty() {
        checked
            .findings
            .retain(|f| f.file == file && plan.diagnostics.iter().any(|d| d.range == f.range && d.code == f.code));
        eprintln!("gudsl run: `{}` cannot run", plan.diagram);
        return super::refuse(&checked, 1);
    }
    let output_dir = || {
        OutputDir::for_run(args.output, Path::new("."), &plan.diagram).map_err(|error| {
            eprintln!("gudsl run: not writing into the output folder: {error}");
            ExitCode::from(2)
        })
    };
    let study = !args.sweeps.is_empty();
    let jobs = match args.resume {
        true => match output_dir() {
            Ok(output) => not_done(&output, jobs, &settings, study),
            Err(code) => return code,
        },
        false => jobs,
    };
    let original = host.analysis().file_text(plan.file).to_string();
    let mut worst = 0;
    let mut planned = Vec::new();
    for (k, job) in jobs.iter().enumerate() {
        let mut runs = Vec::new();
        for setting in &settings {
            let setting = job.as_ref().map_or_else(|| setting.clone(), |r| batch::with_recording(setting, r));
            let made = if setting.assignments.is_empty() {
                prepare_as_checked(&host.analysis(), preparations, &plan, &mut checked, file)
            } else {
                prepare_setting(host, preparations, &plan, &original, &setting, job.as_ref())
            };
            match made {
                Ok(mut prepared) => {
                    if args.one_frame_at_a_time {
                        prepared.one_frame_at_a_time();
                    }
                    if args.unfused {
                        prepared.unfused();
                    }
                    let folder = batch::folder(job.as_ref(), &setting, study);
                    runs.push(Planned { recording: job.clone(), setting, folder, prepared });
                }
                // A problem of the model or the settings stops every run; one of a recording's
                // files, only that recording's.
                Err(refused) if job.is_none() || (k == 0 && !refused.blames_recording) => {
                    return ExitCode::from(refused.code)
                }
                Err(refused) => {
                    let name = job.as_ref().map_or("", |r| r.name.as_str());
                    eprintln!("gudsl run: recording `{name}` cannot run; the others go on");
                    worst = worst.max(refused.code);
                    runs.clear();
                    break;
                }
            }
        }
        planned.extend(runs);
    }
    // Made once every run is prepared: a refused pipeline writes nothing.
    let mut output = match output_dir() {
        Ok(output) => output,
        Err(code) => return code,
    };
    let gpu = pipeline::gpu(args.cpu, |error| {
        eprintln!("gudsl run: no GPU adapter ({error}); running on the CPU reference (--cpu says so)")
    });
    let ran = run_all(planned, gpu.as_ref(), &mut output, args.frames, study);
    worst = worst.max(ran);
    if args.inputs.is_some() {
        worst = worst.max(match shard {
            None => summarize(&mut output),
            Some(shard) => {
                println!(
                    "shard {}/{} done; once every shard is, `gudsl summarize {}` writes the summary",
                    shard.index,
                    shard.count,
                    output.path().display()
                );
                0
            }
        });
    }
    ExitCode::from(worst)
}

/// The settings, the jobs (a recording each, or one without) and the shard of a run.
type Jobs = (Vec<Setting>, Vec<Option<Recording>>, Option<Shard>);

/// The settings and jobs (a recording each, or one without) `args` asks for, with the shard.
fn settings_and_jobs(args: &PipelineArgs) -> Result<Jobs, String> {
    let settings = settings::grid(args.sets, args.sweeps)?;
    let names_recording = settings.iter().any(batch::names_recording);
    let Some(pattern) = args.inputs else {
        if names_recording {
            return Err(format!("a value names `{}`: give the recordings with --inputs", batch::PLACEHOLDER));
        }
        if args.shard.is_some() || args.resume {
            return Err("--shard and --resume share out and skip recordings: give them with --inputs".to_string());
        }
        return Ok((settings, vec![None], None));
    };
    if !names_recording {
        return Err(format!(
            "no value of --set or --sweep names `{}`: say which parameter reads each recording (as --set 'Camera.path={}')",
            batch::PLACEHOLDER,
            batch::PLACEHOLDER
        ));
    }
    let shard = match args.shard {
        Some(shard) => Some(shard),
        None => batch::shard_from_env(|name| std::env::var(name).ok())?,
    };
    let recordings = batch::mine(batch::recordings(pattern)?, shard);
    eprintln!(
        "{} recordings to run{}",
        recordings.len(),
        shard.map_or(String::new(), |s| format!(" in shard {}/{}", s.index, s.count))
    );
    Ok((settings, recordings.into_iter().map(Some).collect(), shard))
}

/// The jobs whose runs are not all done already (`--resume`).
fn not_done(
    output: &OutputDir,
    jobs: Vec<Option<Recording>>,
    settings: &[Setting],
    study: bool,
) -> Vec<Option<Recording>> {
    let rows = match rows_beneath(output, 2) {
        Ok((rows, _)) => rows,
        Err(error) => {
            eprintln!("gudsl run: --resume: {error}; running every recording");
            return jobs;
        }
    };
    let reports: HashMap<String, StudyRow> = rows.into_iter().map(|row| (row.folder.clone(), row)).collect();
    let before = jobs.len();
    let left: Vec<Option<Recording>> = jobs
        .into_iter()
        .filter(|job| !job.as_ref().is_some_and(|r| batch::done(&reports, r, settings, study)))
        .collect();
    eprintln!("--resume: {} of {before} recordings done already", before - left.len());
    left
}

/// Runs each planned run into its folder; a study's table and files once a job's settings
/// ran (at the top of the output folder, or of the recording's). The worst exit code.
fn run_all(planned: Vec<Planned>, gpu: Option<&Gpu>, output: &mut OutputDir, frames: Option<usize>, study: bool) -> u8 {
    let (mut worst, mut rows) = (0, Vec::new());
    let total = planned.len();
    let mut planned = planned.into_iter().enumerate().peekable();
    while let Some((k, run)) = planned.next() {
        if total > 1 {
            eprintln!("run {}/{total}: {}", k + 1, run.folder);
        }
        let mut ran_with: Vec<(String, String)> =
            run.recording.iter().map(|r| ("recording".to_string(), r.name.clone())).collect();
        ran_with.extend(run.setting.swept.iter().cloned());
        let nested = run
            .folder
            .split('/')
            .filter(|p| !p.is_empty())
            .try_fold(None::<OutputDir>, |at, part| at.as_ref().unwrap_or(output).nested(part).map(Some));
        let mut nested = match nested {
            Ok(nested) => nested,
            Err(error) => {
                eprintln!("gudsl run: {error}");
                worst = 2;
                continue;
            }
        };
        let target = match nested.as_mut() {
            Some(nested) => nested,
            None => &mut *output,
        };
        let (report, code) = run_one(run.prepared, gpu, target, frames, ran_with);
        worst = worst.max(code);
        if !study {
            continue;
        }
        rows.push(StudyRow::of(run.setting.swept.clone(), run.setting.folder(), &report));
        let job_ends = planned.peek().is_none_or(|(_, next)| next.recording != run.recording);
        if job_ends {
            let at = run.recording.as_ref().map(|r| output.nested(&r.name));
            let written = match at {
                Some(Ok(mut folder)) => print_study(&std::mem::take(&mut rows), &mut folder),
                Some(Err(error)) => Err(error),
                None => print_study(&std::mem::take(&mut rows), output),
            };
            if let Err(error) = written {
                eprintln!("gudsl run: {error}");
                worst = 2;
            }
        }
    }
    worst
}

fn print_study(rows: &[StudyRow], folder: &mut OutputDir) -> Result<(), String> {
    println!("\nstudy of {} settings", rows.len());
    print!("{}", study_table(rows));
    write_study(rows, "study", folder)?;
    println!("wrote study.csv, study.svg and study.png in {}", folder.path().display());
    Ok(())
}

/// The summary of every recording's runs beneath `output` (this process's and any other's):
/// printed, and `summary.csv`, `.svg`, `.png` at its top. The exit code: 2 when not written.
pub fn summarize(output: &mut OutputDir) -> u8 {
    let (rows, unread) = match rows_beneath(output, 2) {
        Ok(found) => found,
        Err(error) => {
            eprintln!("gudsl: {error}");
            return 2;
        }
    };
    for folder in unread {
        eprintln!("warning: {folder}/report.json is no run's report; left out of the summary");
    }
    let rows: Vec<StudyRow> =
        rows.into_iter().filter(|row| row.setting.first().is_some_and(|(name, _)| name == "recording")).collect();
    println!("\nsummary of {} runs", rows.len());
    print!("{}", study_table(&rows));
    if let Err(error) = write_study(&rows, "summary", output) {
        eprintln!("gudsl: {error}");
        return 2;
    }
    println!("wrote summary.csv, summary.svg and summary.png in {}", output.path().display());
    0
}

fn cancelled() -> ExitCode {
    eprintln!("gudsl run: the analysis was cancelled");
    ExitCode::from(2)
}

/// The pipeline `plan` as the check prepared it; its problems refused as the check's findings.
fn prepare_as_checked(
    analysis: &Analysis,
    preparations: &Preparations,
    plan: &PipelinePlan,
    checked: &mut report::Report,
    file: usize,
) -> Result<PreparedPipeline, Refused> {
    match preparations.take_for(analysis, plan) {
        Err(_) => {
            cancelled();
            Err(Refused { code: 2, blames_recording: false })
        }
        Ok(Ok(prepared)) => Ok(prepared),
        Ok(Err(errors)) => {
            let code = if errors.iter().any(|e| e.kind == ErrorKind::Input) { 2 } else { 1 };
            checked.findings.clear();
            add_findings(checked, file, &errors);
            eprintln!("gudsl run: `{}` cannot run", plan.diagram);
            super::refuse(checked, code);
            Err(Refused { code, blames_recording: false })
        }
    }
}

/// The pipeline with `setting` written into the model: its problems told at the value that
/// caused them (`--set A.b=1: …`), or with the setting.
fn prepare_setting(
    host: &mut AnalysisHost,
    preparations: &Preparations,
    base: &PipelinePlan,
    original: &str,
    setting: &Setting,
    recording: Option<&Recording>,
) -> Result<PreparedPipeline, Refused> {
    let label = recording.map_or(String::new(), |r| format!("{}: ", r.name));
    let ranges = settings::apply(host, base.file, original, &base.diagram, setting).map_err(|why| {
        eprintln!("{label}error[{}]: {why}", DiagnosticCode::ParameterValue.as_str());
        Refused { code: 1, blames_recording: false }
    })?;
    let analysis = host.analysis();
    let blames_recording = std::cell::Cell::new(false);
    let told = |severity: Severity, code: DiagnosticCode, range: Option<TextRange>, message: &str| {
        let severity = if severity == Severity::Error { "error" } else { "warning" };
        let given = range.and_then(|r| ranges.iter().position(|v| v.contains_range(r) || r.contains_range(*v)));
        let path = recording.map(|r| r.path.to_string_lossy().into_owned());
        match given {
            Some(k) => {
                let assignment = &setting.assignments[k];
                if path.as_ref().is_some_and(|p| assignment.value.contains(p.as_str())) {
                    blames_recording.set(true);
                }
                eprintln!("{label}{severity}[{}]: {}: {message}", code.as_str(), setting.given(assignment))
            }
            None => eprintln!("{label}{severity}[{}]: {message} (with {})", code.as_str(), all_given(setting)),
        }
    };
    let refused = |code: u8| Refused { code, blames_recording: blames_recording.get() };
    // Checked as the file is checked: the model's rules, the kernels, the pipeline's files.
    let Ok(diagnostics) = file_diagnostics(&analysis, base.file, preparations) else { return Err(refused(2)) };
    diagnostics.iter().for_each(|d| told(d.severity, d.code, Some(d.range), &d.message));
    if diagnostics.iter().any(|d| d.severity == Severity::Error) {
        let input = diagnostics.iter().any(|d| d.code == DiagnosticCode::PipelineInput);
        return Err(refused(if input { 2 } else { 1 }));
    }
    let Ok(Some(plan)) = analysis.pipeline_plan(&base.diagram) else { return Err(refused(2)) };
    match preparations.take_for(&analysis, &plan) {
        Err(_) => Err(refused(2)),
        Ok(Err(errors)) => {
            // What the file's diagnostics do not tell: a component the runtime cannot run.
            let not_told = errors.iter().filter(|e| e.kind == ErrorKind::NotRunnable);
            not_told.for_each(|e| told(Severity::Error, e.code(), e.range, &e.to_string()));
            Err(refused(1))
        }
        Ok(Ok(prepared)) => Ok(prepared),
    }
}

/// Why a run cannot be made, told already: its exit code, and whether a value naming the
/// recording's files is to blame (the recording fails alone).
struct Refused {
    code: u8,
    blames_recording: bool,
}

fn all_given(setting: &Setting) -> String {
    setting.assignments.iter().map(|a| setting.given(a)).collect::<Vec<_>>().join(" ")
}

/// Runs one prepared pipeline into `output`: its report printed and written, and the exit
/// code — 0 done, 1 a stage failed, 2 an output not written.
fn run_one(
    mut prepared: PreparedPipeline,
    gpu: Option<&Gpu>,
    output: &mut OutputDir,
    frames: Option<usize>,
    setting: Vec<(String, String)>,
) -> (PipelineReport, u8) {
    let count = frames.map_or(prepared.frames(), |n| n.min(prepared.frames()));
    let device = gpu.map_or_else(|| "the CPU reference".to_string(), |g| g.describe());
    eprintln!("running {} ({count} frames) on {device}", prepared.diagram());
    let mut progress = Progress::new(count);
    let mut report = prepared.run(gpu, output, frames, &mut progress, &AtomicBool::new(false));
    report.setting = setting;
    progress.done();
    print_report(&report);
    if let Err(error) = write_report(&report, output) {
        eprintln!("gudsl run: {error}");
        return (report, 2);
    }
    // A sink that failed failed alone: the others wrote everything; the run still fails.
    for error in report.failed_stages() {
        eprintln!("error: {error}");
    }
    let code = match &report.outcome {
        Ok(()) if report.failed_stages().next().is_some() => 1,
        Ok(()) => 0,
        Err(error) => {
            eprintln!("error: {error}");
            if error.kind == ErrorKind::Output {
                2
            } else {
                1
            }
        }
    };
    (report, code)
}

/// The pipeline's problems as findings of the report `gudsl check` writes.
fn add_findings(report: &mut report::Report, file: usize, errors: &[PipelineError]) {
    for error in errors {
        let Some(range) = error.range else {
            eprintln!("error: {error}");
            continue;
        };
        report.findings.push(Finding {
            file,
            severity: Severity::Error,
            code: error.code(),
            message: error.message.clone(),
            range,
            related: Vec::new(),
        });
    }
    report.findings.sort_by_key(|f| (f.file, f.range.start()));
}

/// A progress bar on a terminal, a line a frame otherwise.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
}

impl Progress {
    fn new(frames: usize) -> Progress {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(frames as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template("  frame {pos}/{len} {wide_bar} {elapsed} (eta {eta})")
                    .expect("a valid template"),
            );
            bar
        });
        Progress { bar }
    }

    fn done(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl PipelineObserver for Progress {
    fn frame(&mut self, index: usize, frames: usize) {
        match &self.bar {
            Some(bar) => bar.set_position(index as u64 + 1),
            None => eprintln!("  frame {}/{frames}", index + 1),
        }
    }
}

/// How the run ended, the stages' table and the files written.
fn print_report(report: &PipelineReport) {
    println!("{}", summary(report));
    print!("{}", table(report));
    println!("wrote {} files under the output folder", report.outputs.len());
    for path in report.outputs.iter().filter(|p| !is_frame_file(p)) {
        println!("  {}", path.display());
    }
}

/// A file of one frame (`distance_0003.npy`): listed in `report.json`, not on the terminal.
fn is_frame_file(path: &Path) -> bool {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
    stem.rsplit('_').next().is_some_and(|n| n.len() == 4 && n.chars().all(|c| c.is_ascii_digit()))
}
