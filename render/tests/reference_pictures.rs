//! Reference pictures, as resvg tests itself: diagrams of every kind rendered to PNG as
//! `gudsl render` draws them (at scale 1) and compared pixel by pixel with the reviewed
//! pictures in `tests/reference/` (its README says what was checked in each). A difference
//! fails with the number of pixels that differ and writes the picture drawn and a diff image
//! (differing pixels red over the faded reference) under the build's temporary folder;
//! `GUDSL_UPDATE_REFERENCES=1 cargo test -p gudsl-render --test reference_pictures` writes the
//! drawn pictures as the new references — review them before committing.

use std::path::{Path, PathBuf};

use gudsl_model::{graph::Graph, AnalysisHost};
use gudsl_render::{
    layout::Page,
    png,
    scene::{self, Hints},
};
use resvg::tiny_skia::{Pixmap, PremultipliedColorU8};

mod common {
    pub(crate) mod samples;
}
use common::samples::{sample, sample_graphs};

/// The diagrams drawn, by id: at least one of each kind, and each notation the issue names.
const PICTURES: &[&str] = &[
    // Class diagrams: association ends, qualifiers and static members, interfaces realized.
    "Associations",
    "Qualifiers",
    "ComponentClassDefinitions",
    // Activity diagrams: frame header, decisions and merges, loops as expansion regions.
    "AdFilterMean",
    "LoopWindowExample",
    "TransitionExample",
    // Component diagrams: dataflow left to right, ports and their modes, nesting.
    "ComponentExampleComponents",
    "ComponentExampleDiagram",
    "NestedComponents",
    // Component-instance diagrams: instances, port instances and bindings.
    "ComponentExamplePipeline",
    "ComponentInstanceExampleDiagram",
];

/// Diagrams of the models in `tests/reference/models/` (file stem = diagram id), each drawn
/// for a page (a paper's name as `gudsl render --page` takes it, or none for the screen):
/// generated at sizes the samples do not reach.
const MODELS: &[(&str, Option<&str>)] = &[
    // A control flow taller than a screen, wrapped into columns.
    ("LongFlow", None),
    // 200 classes far wider than an upright A4 page as their ranks come, narrowed to it.
    ("Classes200", Some("A4")),
    // A pipeline of 60 instances, far wider than a screen in one row, wrapped into rows.
    ("LongPipeline", None),
];

/// A channel may differ by this much (rounding in the rasterizer) before the pixel counts as
/// different.
const CHANNEL_TOLERANCE: u8 = 2;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

#[test]
fn diagrams_look_like_their_reviewed_reference_pictures() {
    let graphs = sample_graphs();
    let references = root().join("tests/reference");
    let update = std::env::var_os("GUDSL_UPDATE_REFERENCES").is_some_and(|v| v == "1");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-pictures");
    let mut failures = Vec::new();
    let page = |paper: Option<&str>| paper.map_or(Page::SCREEN, |name| Page::paper(name).expect("a known paper"));
    let models: Vec<(Graph, Page)> = MODELS.iter().map(|&(id, paper)| (model(&references, id), page(paper))).collect();
    let drawings = PICTURES
        .iter()
        .map(|id| (*id, sample(&graphs, id), Page::default()))
        .chain(models.iter().zip(MODELS).map(|((graph, page), (id, _))| (*id, graph, *page)));
    for (id, graph, page) in drawings {
        let scene = scene::build(graph, Hints { page, ..Hints::default() });
        let drawn = png::to_png(&gudsl_render::svg::write(&scene), 1.0).unwrap();
        let reference = references.join(format!("{id}.png"));
        if update {
            std::fs::write(&reference, &drawn).unwrap();
            continue;
        }
        let expected = std::fs::read(&reference).unwrap_or_else(|e| {
            panic!("{}: {e} (GUDSL_UPDATE_REFERENCES=1 draws it; review it before committing)", reference.display())
        });
        if let Some(difference) = compare(&Pixmap::decode_png(&expected).unwrap(), &Pixmap::decode_png(&drawn).unwrap())
        {
            std::fs::create_dir_all(&out).unwrap();
            let (actual, diff) = (out.join(format!("{id}.png")), out.join(format!("{id}.diff.png")));
            std::fs::write(&actual, &drawn).unwrap();
            difference.image.save_png(&diff).unwrap();
            failures.push(format!("{id}: {} (drawn: {}, diff: {})", difference.what, actual.display(), diff.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "pictures differ from their references in {}:\n{}\nif the change is meant, rerun with GUDSL_UPDATE_REFERENCES=1 and review the pictures",
        references.display(),
        failures.join("\n")
    );
}

/// The diagram `id` of `models/<id>.gudsl`.
fn model(references: &Path, id: &str) -> Graph {
    let path = references.join("models").join(format!("{id}.gudsl"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // With the seed's listings, whose classes a model may instantiate.
    let seed = root().join("../samples/seed");
    let mut listings: Vec<PathBuf> = std::fs::read_dir(&seed).unwrap().flatten().map(|e| e.path()).collect();
    listings.retain(|p| p.extension().is_some_and(|e| e == "gudsl"));
    listings.sort();
    let files = std::iter::once((path.display().to_string(), text))
        .chain(listings.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).unwrap())));
    let (host, files) = AnalysisHost::with_files(files);
    let graphs = host.analysis().graphs(files[0]).unwrap().to_vec();
    graphs.into_iter().find(|g| g.id == id).unwrap_or_else(|| panic!("{}: no diagram `{id}`", path.display()))
}

/// How a picture differs from its reference: in words, and as an image.
struct Difference {
    what: String,
    image: Pixmap,
}

/// `None` where `drawn` is `expected` (every channel within `CHANNEL_TOLERANCE`), else the
/// difference: the reference faded, the pixels that differ red (over both sizes, where they
/// differ).
fn compare(expected: &Pixmap, drawn: &Pixmap) -> Option<Difference> {
    let (width, height) = (expected.width().max(drawn.width()), expected.height().max(drawn.height()));
    let pixel = |p: &Pixmap, x: u32, y: u32| p.pixel(x, y);
    let mut image = Pixmap::new(width, height).unwrap();
    let red = PremultipliedColorU8::from_rgba(255, 0, 0, 255).unwrap();
    let mut differing = 0usize;
    for y in 0..height {
        for x in 0..width {
            let (a, b) = (pixel(expected, x, y), pixel(drawn, x, y));
            let same = match (a, b) {
                (Some(a), Some(b)) => {
                    let channels = |c: PremultipliedColorU8| [c.red(), c.green(), c.blue(), c.alpha()];
                    channels(a).iter().zip(channels(b)).all(|(p, q)| p.abs_diff(q) <= CHANNEL_TOLERANCE)
                }
                _ => false,
            };
            let shown = if same {
                // The reference, faded to a light grey.
                let c = a.expect("same pixels exist");
                let fade = |v: u8| 255 - (255 - v) / 4;
                PremultipliedColorU8::from_rgba(fade(c.red()), fade(c.green()), fade(c.blue()), 255).unwrap()
            } else {
                differing += 1;
                red
            };
            image.pixels_mut()[(y * width + x) as usize] = shown;
        }
    }
    let sizes = if (expected.width(), expected.height()) == (drawn.width(), drawn.height()) {
        String::new()
    } else {
        format!(", size {}×{} instead of {}×{}", drawn.width(), drawn.height(), expected.width(), expected.height())
    };
    (differing > 0).then(|| Difference { what: format!("{differing} pixels differ{sizes}"), image })
}
