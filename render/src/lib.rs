//! Diagram rendering (graph view -> layout -> SVG/PNG); built in a later issue.
