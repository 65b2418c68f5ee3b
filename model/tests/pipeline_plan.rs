//! The pipeline plan of a component-instance diagram: stages in the order data flows (a loop
//! closed by a buffered port included), parameters with their defaults and written values,
//! bindings from provider to processor with the receiving port's mode; and incrementality,
//! counted query by query: an edit elsewhere does not rebuild the plan, a parameter edited does.

use gudsl_model::ide::parameter_edit;
use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace, EDITED, UNEDITED},
    hir::{
        file_diagnostics,
        pipeline::{pipeline_plan, PipelinePlan, Value},
        Fqn,
    },
};
use salsa::Setter;

const PIPELINE: &str = r#"
ComponentInstanceDiagram ClosedLoop
{
    import ToF.*;

    // Declared consumer first: the plan orders by data, not by text.
    Control instantiates IntegrationTimeControl (method = IntegrationControl.MeanIntensity)
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
        Out : TimeOut ( provider time = IIntegrationTimeProvider() );
        [ source Out.time ==> target Camera.Time.time ]
    }
    Demod instantiates Demodulation (modulationFrequency = 20)
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Control.In.depth ]
    }
    Camera instantiates ControlledCamera (scene = Scene.Plates, frames = 2 * 6)
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        Time : TimeIn ( processor time = IIntegrationTimeProcessor(bufferSize = 1) );
        [ source Out.frame ==> target Demod.In.frame ]
    }
}
"#;

const ELSEWHERE: &str = r#"
ClassDiagram Other { public class Thing { public int value; } }
ActivityDiagram Work(Other.Thing thing)
{
    start begin { thing.value = 1; => done; }
    final done;
}
"#;

struct Workspace2 {
    db: RootDatabase,
    workspace: Workspace,
    pipeline: SourceFile,
    elsewhere: SourceFile,
}

fn workspace() -> Workspace2 {
    let db = RootDatabase::with_execution_log();
    let pipeline = SourceFile::builder("pipeline.gudsl".into(), PIPELINE.into()).durability(UNEDITED).new(&db);
    let elsewhere = SourceFile::builder("other.gudsl".into(), ELSEWHERE.into()).durability(UNEDITED).new(&db);
    let library = gudsl_model::library::library_files(&db);
    let workspace = Workspace::new(&db, library.into_iter().chain([pipeline, elsewhere]).collect());
    Workspace2 { db, workspace, pipeline, elsewhere }
}

fn plan(w: &Workspace2) -> PipelinePlan {
    pipeline_plan(&w.db, w.workspace, Fqn::new(&w.db, "ClosedLoop".to_string())).clone().expect("the diagram")
}

fn ran(log: &[String], query: &str) -> usize {
    log.iter().filter(|e| e.starts_with(&format!("{query}("))).count()
}

#[test]
fn stages_follow_the_data_and_parameters_resolve() {
    let w = workspace();
    let plan = plan(&w);
    assert!(plan.diagnostics.is_empty(), "{:#?}", plan.diagnostics);
    let order: Vec<&str> = plan.stages.iter().map(|s| s.instance.as_str()).collect();
    assert_eq!(order, ["Camera", "Demod", "Control"]);
    let camera = &plan.stages[0];
    assert_eq!(camera.class, "ToF.ControlledCamera");
    assert_eq!(camera.param("frames"), Some(&Value::Int(12)));
    assert_eq!(camera.param("scene"), Some(&Value::Enum("Plates".into())));
    // Inherited from SimulatedPmdCamera, its default.
    assert_eq!(camera.param("integrationTime").and_then(Value::number), Some(1000.0));
    assert_eq!(plan.stages[2].param("method"), Some(&Value::Enum("MeanIntensity".into())));
    // Control → Camera closes the loop through the buffered TimeIn, one item deep.
    let feedback = plan.bindings.iter().find(|b| b.processor.stage == 0).expect("the loop's binding");
    assert_eq!((feedback.provider.stage, feedback.provider.port.as_str()), (2, "TimeOut"));
    assert!(feedback.is_buffered && feedback.is_async);
    assert_eq!(feedback.buffer_size, 1);
    let raw = plan.bindings.iter().find(|b| b.provider.port == "RawOut").expect("raw frames");
    assert_eq!((raw.provider.stage, raw.processor.stage, raw.is_buffered), (0, 1, false));
    assert_eq!(raw.buffer_size, 4, "the interface's default");
}

#[test]
fn an_edit_elsewhere_does_not_rebuild_the_plan_and_a_parameter_edit_does() {
    let mut w = workspace();
    plan(&w);
    file_diagnostics(&w.db, w.workspace, w.pipeline);
    w.db.take_executions();

    let text = w.elsewhere.text(&w.db).replace("thing.value = 1;", "thing.value = 2;");
    w.elsewhere.set_text(&mut w.db).with_durability(EDITED).to(text);
    plan(&w);
    file_diagnostics(&w.db, w.workspace, w.pipeline);
    let log = w.db.take_executions();
    assert_eq!(ran(&log, "pipeline_plan"), 0, "an activity body elsewhere: {log:#?}");
    assert_eq!(ran(&log, "check_file"), 0, "the pipeline's file is not re-checked: {log:#?}");

    let text = w.pipeline.text(&w.db).replace("frames = 2 * 6", "frames = 7");
    w.pipeline.set_text(&mut w.db).with_durability(EDITED).to(text);
    let edited = plan(&w);
    assert_eq!(ran(&w.db.take_executions(), "pipeline_plan"), 1);
    assert_eq!(edited.stages[0].param("frames"), Some(&Value::Int(7)));
}

/// The plan with `before` replaced by `after` in the pipeline's text.
fn edited_plan(before: &str, after: &str) -> (Workspace2, PipelinePlan) {
    let mut w = workspace();
    let text = w.pipeline.text(&w.db).replace(before, after);
    assert_ne!(&text, w.pipeline.text(&w.db), "`{before}` is in the text");
    w.pipeline.set_text(&mut w.db).with_durability(EDITED).to(text);
    let plan = plan(&w);
    (w, plan)
}

#[test]
fn values_convert_to_their_fields_type_as_c_converts_constants() {
    let (w, plan) = edited_plan("frames = 2 * 6", "frames = 2.5");
    let [problem] = &plan.diagnostics[..] else { panic!("{:#?}", plan.diagnostics) };
    assert_eq!(problem.code.as_str(), "E0403");
    assert_eq!(problem.message, "`frames` is 2.5, but must be a whole number");
    let at = w.pipeline.text(&w.db).find("2.5").unwrap();
    assert_eq!(usize::from(problem.range.start()), at, "at the value written");

    let (_, plan) = edited_plan("frames = 2 * 6", "frames = 24.0 / 2");
    assert!(plan.diagnostics.is_empty(), "{:#?}", plan.diagnostics);
    assert_eq!(plan.stages[0].param("frames"), Some(&Value::Int(12)), "a whole number is an integer");
    let (_, plan) = edited_plan("modulationFrequency = 20", "modulationFrequency = true");
    assert_eq!(plan.stages[1].param("modulationFrequency"), Some(&Value::Int(1)), "C's true is 1");

    // A value of another kind is validation's to report (E0225), once.
    let (w, plan) = edited_plan("scene = Scene.Plates", "scene = IntegrationControl.MeanIntensity");
    assert!(plan.diagnostics.is_empty(), "{:#?}", plan.diagnostics);
    let codes: Vec<&str> = file_diagnostics(&w.db, w.workspace, w.pipeline).iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["E0225"]);
}

/// `instance.parameter = value` set by an edit of the text, as `gudsl run --set` does: the
/// edited text and the value's range in it.
fn set(w: &Workspace2, instance: &str, parameter: &str, value: &str) -> Result<(String, String), String> {
    let edit = parameter_edit(&w.db, w.workspace, "ClosedLoop", instance, parameter, value)?;
    assert_eq!(edit.file, w.pipeline);
    let text = w.pipeline.text(&w.db).clone();
    let mut edited = text.clone();
    edited.replace_range(std::ops::Range::<usize>::from(edit.range), &edit.text);
    let at = edited[std::ops::Range::<usize>::from(edit.value)].to_string();
    Ok((edited, at))
}

#[test]
fn a_parameter_is_set_where_it_is_written_or_added_to_the_instance() {
    let mut w = workspace();
    let (edited, value) = set(&w, "Demod", "modulationFrequency", "30").unwrap();
    assert!(edited.contains("Demodulation (modulationFrequency = 30)"), "replaced where written");
    assert_eq!(value, "30");
    let (edited, value) = set(&w, "Camera", "seed", " 7 ").unwrap();
    assert!(edited.contains("(scene = Scene.Plates, frames = 2 * 6, seed = 7)"), "after the last: {edited}");
    assert_eq!(value, "7");
    w.pipeline.set_text(&mut w.db).with_durability(EDITED).to(edited);
    assert_eq!(plan(&w).stages[0].param("seed"), Some(&Value::Int(7)), "the plan runs with it");

    for (before, after, wanted) in [
        (
            "IntegrationTimeControl (method = IntegrationControl.MeanIntensity)",
            "IntegrationTimeControl ( )",
            "IntegrationTimeControl (method = IntegrationControl.MeanIntensity)",
        ),
        ("Demodulation (modulationFrequency = 20)", "Demodulation", "Demodulation (modulationFrequency = 25)"),
    ] {
        let mut w = workspace();
        let text = w.pipeline.text(&w.db).replace(before, after);
        w.pipeline.set_text(&mut w.db).with_durability(EDITED).to(text);
        let (parameter, value) = if wanted.contains("method") {
            ("method", "IntegrationControl.MeanIntensity")
        } else {
            ("modulationFrequency", "25")
        };
        let instance = if wanted.contains("method") { "Control" } else { "Demod" };
        let (edited, at) = set(&w, instance, parameter, value).unwrap();
        assert!(edited.contains(wanted), "{edited}");
        assert_eq!(at, value);
    }
}

#[test]
fn a_parameter_edit_names_what_there_is_and_writes_one_value_only() {
    let w = workspace();
    let error = set(&w, "Demodd", "modulationFrequency", "30").unwrap_err();
    assert_eq!(error, "`ClosedLoop` has no instance `Demodd` (it has Camera, Demod, Control)");
    let error = set(&w, "Demod", "frequency", "30").unwrap_err();
    assert!(
        error.starts_with(
            "`Demod` (ToF.Demodulation) has no parameter `frequency` (its parameters: modulationFrequency"
        ),
        "{error}"
    );
    for sneaky in ["30, modulationFrequency = 40", "30) { } X instantiates Y (", "30 /* a */", "", "(scene = Scene.Box"]
    {
        assert!(set(&w, "Demod", "modulationFrequency", sneaky).is_err(), "`{sneaky}` is refused");
        assert!(set(&w, "Camera", "seed", sneaky).is_err(), "`{sneaky}` is refused where it would be added");
    }
    // A value of the wrong type is written: the plan tells what is wrong with it (E0403).
    assert!(set(&w, "Demod", "modulationFrequency", "true").is_ok());
}

#[test]
fn text_a_shell_left_unquoted_is_written_as_text() {
    let pipeline = r#"
ComponentInstanceDiagram Recorded
{
    import ToF.*;
    Truth instantiates AccuracyReport (maxTrueDistance = 3)
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"#;
    let db = RootDatabase::default();
    let file = SourceFile::builder("recorded.gudsl".into(), pipeline.into()).new(&db);
    let library = gudsl_model::library::library_files(&db);
    let workspace = Workspace::new(&db, library.into_iter().chain([file]).collect());
    let edit = |value: &str| parameter_edit(&db, workspace, "Recorded", "Truth", "groundTruth", value);
    assert_eq!(edit("truth/wall.npy").unwrap().text, r#", groundTruth = "truth/wall.npy""#);
    assert_eq!(edit(r#""quoted.npy""#).unwrap().text, r#", groundTruth = "quoted.npy""#);
    assert_eq!(edit(r#"say "hi".npy"#).unwrap().text, r#", groundTruth = "say \"hi\".npy""#);
    // A number is no text: the field is checked as typed.
    let number = parameter_edit(&db, workspace, "Recorded", "Truth", "maxTrueDistance", "x.npy").unwrap();
    assert_eq!(number.text, "x.npy");
}
