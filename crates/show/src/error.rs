//! The crate's one error type: each variant says what cannot be shown and names the file, so
//! a front end can print it as it is.

/// Everything building a viewer page or drawing a plot can fail with.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A trial with no 3D points, where a picture needs some.
    #[error("{file} has no 3D points")]
    NoPoints { file: String },
    /// A trial whose points are all model outputs (angles, moments): nothing to draw in 3D.
    #[error("{file} has only model outputs (angles, moments, …), no markers to show")]
    OnlyModelOutputs { file: String },
    /// The viewer was given a trial with no points at all.
    #[error("{file} has no 3D points to show")]
    NothingToShow { file: String },
    /// The original to compare with has no points.
    #[error("{original} has no 3D points to compare with")]
    NothingToCompare { original: String },
    /// The original to compare with shares no marker label with the file.
    #[error("{original} shares no marker label with {file}")]
    NoSharedLabel { file: String, original: String },
    /// Two BVH files compared whose joints and End Sites differ.
    #[error(
        "{file} and {original} have different skeletons: only in {file}: [{}]; only in {original}: [{}]",
        only_in_file.join(", "),
        only_in_original.join(", ")
    )]
    DifferentSkeletons {
        file: String,
        original: String,
        only_in_file: Vec<String>,
        only_in_original: Vec<String>,
    },
    /// A marker asked for by name that the file does not have.
    #[error("{file} has no marker {name:?}; available: {}", available.join(", "))]
    NoMarker {
        file: String,
        name: String,
        available: Vec<String>,
    },
    /// An analog channel asked for where the file has none.
    #[error("{file} has no analog channels")]
    NoAnalog { file: String },
    /// An analog channel asked for by name or number that the file does not have.
    #[error("{file} has no analog channel {name:?}; available: {}", available.join(", "))]
    NoAnalogChannel {
        file: String,
        name: String,
        available: Vec<String>,
    },
    /// A marker plot asked for with no marker (each front end says how to name one).
    #[error("no marker given")]
    NoMarkerGiven,
    /// More markers than one picture has columns for.
    #[error("{given} markers given; one plot shows at most {most} (make several plots)")]
    TooManyMarkers { given: usize, most: usize },
    /// A force plot of a trial without plates (`warned`: some were named but could not be
    /// computed, and the warnings say why).
    #[error(
        "{file}: no force platforms{} to plot",
        if *warned { " could be computed (see the warnings)" } else { "" }
    )]
    NoPlates { file: String, warned: bool },
    /// A picture's file name that ends in neither `.svg` nor `.png`.
    #[error("{}: the output must end in .svg or .png", path.display())]
    PictureFormat { path: std::path::PathBuf },
    /// Keyframe error curves with a non-finite value (which would never finish labelling).
    #[error("cannot plot: the error curve is not finite")]
    CurveNotFinite,
    /// The stick figure file is not a JSON list of label pairs.
    #[error("{file}: expected a JSON list of [markerA, markerB] pairs")]
    SticksJson {
        file: String,
        #[source]
        source: serde_json::Error,
    },
    /// A stick of the stick figure file that is not a pair of labels.
    #[error("{file}: each stick is a pair of marker names, found {found:?}")]
    SticksPair { file: String, found: Vec<String> },
    /// The embedded font could not be registered.
    #[error("the embedded font cannot be read")]
    Font,
    /// The drawing library failed (its message).
    #[error("drawing failed: {0}")]
    Draw(String),
    /// Encoding a PNG picture failed.
    #[error(transparent)]
    Png(#[from] png::EncodingError),
    /// The library refused the trial (its force plates, detecting its events).
    #[error(transparent)]
    Library(#[from] c3dfix::Error),
    /// Putting the page's metadata into JSON failed.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

/// The crate's results.
pub type Result<T, E = Error> = std::result::Result<T, E>;
