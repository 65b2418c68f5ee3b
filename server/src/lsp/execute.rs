//! `workspace/executeCommand`: the `gudsl.*` commands (`ext.rs`) dispatched to their features,
//! and a run driven from the message loop's side — prepared on a snapshot, done on a thread of
//! its own with `$/progress`, answered with its report once it ended.

use std::sync::atomic::Ordering;

use gudsl_model::Cancellable;
use tower_lsp_server::{
    jsonrpc::{self, Error},
    ls_types as lsp,
};

use super::{
    ext::{GraphChangedNotification, COMMANDS, PREVIEW, RUN, RUN_PIPELINE, SHOW_WGSL},
    host::Snapshot,
    invalid_params,
    jobs::{spawn, Event, Job, Refusal, RunRequest, WorkDone},
    lock, pipeline, request_failed, run,
    server::Backend,
    wgsl, CLIENT_ANSWER,
};

/// Why nothing runs in a workspace the client does not trust.
const UNTRUSTED: &str =
    "the workspace is not trusted (Restricted Mode): gudsl runs nothing and reads no file a model names until you trust it";

impl Backend {
    /// A command of `ext::COMMANDS`, done; an unknown command is invalid.
    pub(super) async fn execute(&self, params: lsp::ExecuteCommandParams) -> jsonrpc::Result<Option<lsp::LSPAny>> {
        let argument = params.arguments.into_iter().next();
        let token = params.work_done_progress_params.work_done_token;
        match params.command.as_str() {
            RUN => {
                let request = RunRequest::parse(RUN, argument.as_ref()).map_err(invalid_params)?;
                self.run(request, run::prepare, token).await.map(Some)
            }
            RUN_PIPELINE => {
                let request = RunRequest::parse(RUN_PIPELINE, argument.as_ref()).map_err(invalid_params)?;
                self.run(request, pipeline::prepare, token).await.map(Some)
            }
            SHOW_WGSL => {
                let argument = argument.unwrap_or_default();
                self.on_snapshot(move |s| wgsl::show(s, &argument)).await?.map(Some).map_err(request_failed)
            }
            PREVIEW => self.preview(argument.as_ref()).await,
            other => Err(invalid_params(format!("no command `{other}`; the server offers {}", COMMANDS.join(", ")))),
        }
    }

    /// `gudsl.preview`: the live pipeline set (refused while the workspace is not trusted), and
    /// its first preview started.
    async fn preview(&self, argument: Option<&lsp::LSPAny>) -> jsonrpc::Result<Option<lsp::LSPAny>> {
        if !lock(&self.host).trusted() {
            return Err(request_failed(format!("gudsl: {UNTRUSTED}")));
        }
        let (state, start) = self.previews.command(argument).map_err(invalid_params)?;
        if start {
            self.follow_preview(std::time::Instant::now());
        }
        Ok(Some(serde_json::to_value(state).unwrap_or_default()))
    }

    /// Prepares a run on a snapshot (none while the workspace is not trusted), runs it off the message loop with progress, and answers
    /// with the report once it ended (refused, with the problems as `data`, when it cannot
    /// start). `gudsl.run` and `gudsl.runPipeline`.
    pub(super) async fn run(
        &self,
        request: RunRequest,
        prepare: fn(&Snapshot, &RunRequest) -> Cancellable<Result<Job, Refusal>>,
        token: Option<lsp::ProgressToken>,
    ) -> jsonrpc::Result<lsp::LSPAny> {
        let job = match self
            .on_snapshot(move |s| match s.preparations.access().trusted() {
                true => prepare(s, &request),
                false => Ok(Err(Refusal { message: UNTRUSTED.to_string(), problems: Vec::new() })),
            })
            .await?
        {
            Ok(job) => job,
            Err(refusal) => {
                let message = format!("gudsl: {}", refusal.message);
                self.client.show_message(lsp::MessageType::ERROR, message.clone()).await;
                let data = Some(serde_json::json!({ "problems": refusal.problems }));
                return Err(Error { data, ..request_failed(message) });
            }
        };
        let diagram = job.diagram.clone();
        let token = match token {
            Some(token) => Some(token),
            None if self.progress_supported.load(Ordering::SeqCst) => {
                let token = self.runs.new_token();
                let created =
                    tokio::time::timeout(CLIENT_ANSWER, self.client.create_work_done_progress(token.clone())).await;
                created.is_ok_and(|answer| answer.is_ok()).then_some(token)
            }
            None => None,
        };
        // Dropped when the request is cancelled ($/cancelRequest drops this future) or answered:
        // either way the run stops.
        let mut guard = self.runs.start(&token.clone().unwrap_or_else(|| self.runs.new_token()));
        let progress = match token.clone() {
            Some(token) => {
                let progress = WorkDone { client: self.client.clone(), token };
                progress.begin(format!("Running {diagram}"), job.starting, job.bounded).await;
                Some(progress)
            }
            None => None,
        };
        guard.reports(token.clone().filter(|_| progress.is_some()).map(|token| (self.client.clone(), token)));
        let (events, mut received) = tokio::sync::mpsc::unbounded_channel();
        let finished = spawn(job.work, guard.stop_flag(), events);
        while let Some(event) = received.recv().await {
            match event {
                Event::Progress(message, percentage) => {
                    if let Some(progress) = &progress {
                        progress.report(message, percentage).await;
                    }
                }
                Event::Printed(text) => self.client.log_message(lsp::MessageType::INFO, text).await,
            }
        }
        let finished = finished.await.unwrap_or_else(|_| Err("the run's thread ended without an answer".into()));
        guard.reports(None);
        drop(guard);
        let finished = match finished {
            Ok(finished) => finished,
            Err(why) => {
                if let Some(progress) = progress {
                    progress.end(why.clone()).await;
                }
                let message = format!("gudsl: {diagram} did not run: {why}");
                self.client.show_message(lsp::MessageType::ERROR, message.clone()).await;
                return Err(request_failed(message));
            }
        };
        if let Some(progress) = progress {
            progress.end(finished.summary.clone()).await;
        }
        let location = finished.failure.as_ref().and_then(|failure| failure.location.clone());
        let mut answer = match finished.report {
            Ok(report) => report,
            Err(why) => serde_json::json!({ "diagram": diagram, "error": why }),
        };
        let output = finished.output.display();
        answer["output"] = serde_json::json!(output.to_string());
        answer["errorLocation"] = serde_json::to_value(&location).unwrap_or_default();
        if answer["bindings"].is_array() {
            // A pipeline's diagram is drawn with this run's times and flows from now on.
            let snap = lock(&self.host).snapshot(self.encoding());
            let changed = self.scenes.ran(&answer, &snap);
            drop(snap);
            for changed in changed {
                self.client.send_notification::<GraphChangedNotification>(changed).await;
            }
        }
        let (kind, message) = match &finished.failure {
            None => (lsp::MessageType::INFO, format!("gudsl: {}; output in {output}", finished.summary)),
            Some(failure) if failure.cancelled => (lsp::MessageType::INFO, format!("gudsl: {}", finished.summary)),
            Some(failure) => {
                let at =
                    location.map(|l| format!(" at {}:{}", l.uri.as_str(), l.range.start.line + 1)).unwrap_or_default();
                (lsp::MessageType::ERROR, format!("gudsl: {diagram} stopped{at}: {}", failure.message))
            }
        };
        self.client.show_message(kind, message).await;
        Ok(answer)
    }
}
