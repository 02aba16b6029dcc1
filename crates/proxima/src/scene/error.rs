//! What a [`Scene`](super::Scene) refuses.

use crate::error::BuildError;
use crate::index::IndexError;

/// A scene that cannot be made, or a change it cannot take.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// An instance's mesh cannot answer a scene's queries (no faces).
    #[error("instance {instance}: {source}")]
    Mesh {
        /// The instance.
        instance: usize,
        /// Why.
        source: IndexError,
    },
    /// An instance index beyond the scene's.
    #[error("instance {index} is out of range: the scene has {count} instances")]
    InstanceOutOfRange {
        /// The index given.
        index: usize,
        /// The scene's instances.
        count: usize,
    },
    /// An instance placed beyond the coordinates a tree takes.
    #[error("an instance is placed beyond the coordinates a tree takes: {0}")]
    Placement(BuildError),
    /// More instances than 32-bit indices can address.
    #[error("{count} instances is more than 32-bit indices can address")]
    TooMany {
        /// The instances given.
        count: usize,
    },
}
