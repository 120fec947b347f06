//! Undo/redo history of whole documents, with gesture merging: all edits
//! of one kind made during one gesture (a drag, a slider move) form a single
//! undo step.

use fairway::io::Document;

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
    /// Fairing options (end conditions, method, ...).
    Options,
    /// A one-off edit that never merges (accept, load).
    Single,
}

/// Undo and redo stacks of documents.
#[derive(Debug, Default)]
pub struct History {
    undo: Vec<Document>,
    redo: Vec<Document>,
    open: Option<Gesture>,
}

impl History {
    /// Record `before` as an undo step for an edit of kind `g`, unless it
    /// continues the currently open gesture of the same kind.
    pub fn record(&mut self, before: &Document, g: Gesture) {
        if g != Gesture::Single && self.open == Some(g) {
            return;
        }
        self.undo.push(before.clone());
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

    /// Step back: returns the document to restore, storing `current` for redo.
    pub fn undo(&mut self, current: &Document) -> Option<Document> {
        self.open = None;
        let d = self.undo.pop()?;
        self.redo.push(current.clone());
        Some(d)
    }

    /// Step forward again.
    pub fn redo(&mut self, current: &Document) -> Option<Document> {
        self.open = None;
        let d = self.redo.pop()?;
        self.undo.push(current.clone());
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
