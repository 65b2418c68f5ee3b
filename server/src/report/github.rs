//! The report as GitHub Actions workflow commands (`::error file=…,line=…::message`): each
//! problem becomes an annotation on the pull request's diff.

use std::io;

use gudsl_model::hir::Severity;

use super::Report;

/// Escapes a command's message (`%`, CR and LF), as the Actions runner decodes it.
fn escape_data(text: &str) -> String {
    text.replace('%', "%25").replace('\r', "%0D").replace('\n', "%0A")
}

/// Escapes a property value (also `:` and `,`, which separate properties).
fn escape_property(text: &str) -> String {
    escape_data(text).replace(':', "%3A").replace(',', "%2C")
}

pub fn write(report: &Report, out: &mut impl io::Write) -> io::Result<()> {
    for finding in &report.findings {
        let (start, end) = report.span(finding);
        let command = match finding.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        writeln!(
            out,
            "::{command} file={},line={},col={},endLine={},endColumn={},title={}::{}",
            escape_property(report.path(finding)),
            start.line,
            start.column,
            end.line,
            end.column,
            escape_property(&format!("{} {}", finding.code.as_str(), finding.code.summary())),
            escape_data(&finding.message),
        )?;
    }
    for unreadable in &report.unreadable {
        writeln!(
            out,
            "::error file={},title=unreadable::{}",
            escape_property(&unreadable.path.display().to_string()),
            escape_data(&unreadable.message)
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_and_properties_are_escaped() {
        assert_eq!(escape_data("50% a\r\nb"), "50%25 a%0D%0Ab");
        assert_eq!(escape_property("C:\\x,y"), "C%3A\\x%2Cy");
    }
}
