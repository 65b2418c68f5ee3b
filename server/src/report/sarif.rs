//! The report as SARIF 2.1.0 (the format GitHub code scanning uploads), through `serde-sarif`'s
//! types: one run of `gudsl`, a rule per code that occurs, a result per problem with its region
//! (columns counted in Unicode code points, said in `columnKind`) and its related locations (a
//! duplicate's first declaration), and the paths that could not be read as tool execution
//! notifications.

use std::{collections::BTreeMap, io, path::Path};

use gudsl_model::{
    hir::{DiagnosticCode, Severity},
    syntax::TextRange,
};
use serde_json::json;
use serde_sarif::sarif::{
    ArtifactLocation, Invocation, Location, Message, MultiformatMessageString, Notification, PhysicalLocation, Region,
    ReportingConfiguration, ReportingDescriptor, Result as SarifResult, ResultLevel, Run, Sarif, Tool, ToolComponent,
};

use super::Report;

const SCHEMA: &str = "https://json.schemastore.org/sarif-2.1.0.json";
/// Relative paths are relative to this base, the folder `gudsl` ran in.
const SOURCE_ROOT: &str = "%SRCROOT%";

fn level(severity: Severity) -> ResultLevel {
    match severity {
        Severity::Error => ResultLevel::Error,
        Severity::Warning => ResultLevel::Warning,
    }
}

/// A path as a URI reference: relative ones against [`SOURCE_ROOT`], absolute ones as `file:`
/// URIs, every byte outside RFC 3986's unreserved set and `/` percent-encoded.
fn artifact(path: &Path) -> ArtifactLocation {
    let text = path.to_string_lossy().replace('\\', "/");
    let mut encoded = String::with_capacity(text.len());
    for byte in text.bytes() {
        if byte.is_ascii_alphanumeric() || b"-._~/".contains(&byte) {
            encoded.push(byte as char);
        } else {
            encoded.push_str(&format!("%{byte:02X}"));
        }
    }
    if path.is_absolute() {
        ArtifactLocation::builder().uri(format!("file://{encoded}")).build()
    } else {
        ArtifactLocation::builder().uri(encoded.trim_start_matches("./").to_string()).uri_base_id(SOURCE_ROOT).build()
    }
}

/// `range` of checked file `file`: its artifact and region.
fn physical_location(report: &Report, file: usize, range: TextRange) -> PhysicalLocation {
    let (start, end) = report.span_in(file, range);
    let region = Region::builder()
        .start_line(i64::from(start.line))
        .start_column(i64::from(start.column))
        .end_line(i64::from(end.line))
        .end_column(i64::from(end.column))
        .build();
    PhysicalLocation::builder().artifact_location(artifact(Path::new(&report.files[file].path))).region(region).build()
}

pub fn write(report: &Report, out: &mut impl io::Write) -> io::Result<()> {
    // The rules: each code that occurs, in code order.
    let mut codes: Vec<DiagnosticCode> = report.findings.iter().map(|f| f.code).collect();
    codes.sort_by_key(|c| c.as_str());
    codes.dedup();
    let rules: Vec<ReportingDescriptor> = codes
        .iter()
        .map(|code| {
            let severity = report.findings.iter().find(|f| f.code == *code).map_or(Severity::Error, |f| f.severity);
            ReportingDescriptor::builder()
                .id(code.as_str())
                .short_description(MultiformatMessageString::builder().text(code.summary()).build())
                .default_configuration(ReportingConfiguration::builder().level(json!(level(severity))).build())
                .build()
        })
        .collect();
    let results: Vec<SarifResult> = report
        .findings
        .iter()
        .map(|finding| {
            let related: Vec<Location> = finding
                .related
                .iter()
                .enumerate()
                .map(|(id, (file, range, message))| {
                    Location::builder()
                        .id(id as i64)
                        .physical_location(physical_location(report, *file, *range))
                        .message(Message::builder().text(message).build())
                        .build()
                })
                .collect();
            let location = physical_location(report, finding.file, finding.range);
            let result = SarifResult::builder()
                .rule_id(finding.code.as_str())
                .rule_index(codes.iter().position(|c| *c == finding.code).unwrap_or(0) as i64)
                .level(level(finding.severity))
                .message(Message::builder().text(&finding.message).build())
                .locations(vec![Location::builder().physical_location(location).build()]);
            if related.is_empty() {
                result.build()
            } else {
                result.related_locations(related).build()
            }
        })
        .collect();
    let notifications: Vec<Notification> = report
        .unreadable
        .iter()
        .map(|unreadable| {
            let location = Location::builder()
                .physical_location(PhysicalLocation::builder().artifact_location(artifact(&unreadable.path)).build())
                .build();
            Notification::builder()
                .level(json!("error"))
                .message(Message::builder().text(unreadable.to_string()).build())
                .locations(vec![location])
                .build()
        })
        .collect();
    let invocation = Invocation::builder()
        .execution_successful(notifications.is_empty())
        .tool_execution_notifications(notifications)
        .build();
    let mut base_ids = BTreeMap::new();
    if let Ok(cwd) = std::env::current_dir() {
        let mut root = artifact(&cwd);
        root.uri = root.uri.map(|uri| if uri.ends_with('/') { uri } else { uri + "/" });
        base_ids.insert(SOURCE_ROOT.to_string(), root);
    }
    let driver = ToolComponent::builder()
        .name("gudsl")
        .version(env!("CARGO_PKG_VERSION"))
        .semantic_version(env!("CARGO_PKG_VERSION"))
        .rules(rules)
        .build();
    let run = Run::builder()
        .tool(Tool::builder().driver(driver).build())
        .original_uri_base_ids(base_ids)
        .column_kind(json!("unicodeCodePoints"))
        .results(results)
        .invocations(vec![invocation])
        .build();
    let log = Sarif::builder().schema(SCHEMA).version(json!("2.1.0")).runs(vec![run]).build();
    serde_json::to_writer_pretty(&mut *out, &log)?;
    writeln!(out)
}
