//! Undo/redo history of the shell: snapshots of the whole document and the fairing options, with
//! gesture merging: all edits of one kind made during one gesture (a drag, a slider move) form a
//! single undo step. Both workspaces (curve, surface) go through this one history.

use fairway::io::{Document, SceneObject};

use crate::fairing::FairOptions;

/// What one undo step restores: the document and the fairing options.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// The document.
    pub doc: Document,
    /// The fairing options (kept in the settings, edited as commands like the document).
    pub fair: FairOptions,
    /// Every object of the document (the active one as `doc`), with its name and settings.
    pub objects: Vec<SceneObject>,
    /// The active object's index.
    pub active: usize,
    /// The plane 3D curves are drawn on in the 2D canvas.
    pub view_plane: fairway::io::ViewPlane,
}

/// What kind of edit a gesture makes; consecutive edits of the same kind
/// within one open gesture merge into one undo step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gesture {
    /// Region ends.
    Region,
    /// Tolerance.
    Tolerance,
    /// Target curvature edits.
    Target,
    /// Fairing options (end conditions, method, strength, ...).
    Options,
    /// A one-off edit that never merges (accept, load).
    Single,
}

/// Undo and redo stacks of snapshots.
#[derive(Debug, Default)]
pub struct History {
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
    open: Option<Gesture>,
}

impl History {
    /// Record `before` as an undo step for an edit of kind `g`, unless it
    /// continues the currently open gesture of the same kind.
    pub fn record(&mut self, before: Snapshot, g: Gesture) {
        if g != Gesture::Single && self.open == Some(g) {
            return;
        }
        self.undo.push(before);
        self.redo.clear();
        self.open = if g == Gesture::Single { None } else { Some(g) };
        const MAX: usize = 200;
        if self.undo.len() > MAX {
            self.undo.remove(0);
        }
    }

    /// Close the open gesture (call when the pointer is released).
    pub fn end_gesture(&mut self) {
        self.open = None;
    }

    /// Step back: returns the snapshot to restore, storing `current` for redo.
    pub fn undo(&mut self, current: Snapshot) -> Option<Snapshot> {
        self.open = None;
        let d = self.undo.pop()?;
        self.redo.push(current);
        Some(d)
    }

    /// Step forward again.
    pub fn redo(&mut self, current: Snapshot) -> Option<Snapshot> {
        self.open = None;
        let d = self.redo.pop()?;
        self.undo.push(current);
        Some(d)
    }

    /// Whether there is something to undo.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether there is something to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Forget everything (a new document was opened).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}
