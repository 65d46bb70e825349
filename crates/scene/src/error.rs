//! Errors in scene input, located in their source file.

use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene file's path and text, shared by the locations that point into it.
#[derive(Debug)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
    /// The text again, named by the path, for error reports.
    named: NamedSource<String>,
}

impl SourceFile {
    pub fn new(path: impl Into<PathBuf>, text: String) -> Arc<Self> {
        let path = path.into();
        let named = NamedSource::new(path.display().to_string(), text.clone());
        Arc::new(SourceFile { path, text, named })
    }

    /// One-based line and column of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let col = before.rfind('\n').map_or(offset, |nl| offset - nl - 1) + 1;
        (line, col)
    }
}

/// A span of a source file.
#[derive(Clone, Debug)]
pub struct Location {
    pub file: Arc<SourceFile>,
    pub span: Range<usize>,
}

impl Location {
    pub fn new(file: &Arc<SourceFile>, span: Range<usize>) -> Self {
        Location {
            file: file.clone(),
            span,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (line, col) = self.file.line_col(self.span.start);
        write!(f, "{}:{}:{}", self.file.path.display(), line, col)
    }
}

/// What can be wrong with a scene.
#[derive(Debug)]
pub enum SceneError {
    /// A file could not be read at all.
    Io { path: PathBuf, message: String },
    /// Something at a known place in a scene file is wrong.
    At {
        location: Location,
        message: String,
        label: String,
        help: Option<String>,
    },
}

impl SceneError {
    pub fn io(path: &Path, err: impl fmt::Display) -> Self {
        SceneError::Io {
            path: path.to_path_buf(),
            message: err.to_string(),
        }
    }

    pub fn at(location: Location, message: impl Into<String>) -> Self {
        SceneError::At {
            location,
            message: message.into(),
            label: "here".into(),
            help: None,
        }
    }

    /// Replaces the label shown under the culprit.
    pub fn label(mut self, text: impl Into<String>) -> Self {
        if let SceneError::At { label, .. } = &mut self {
            *label = text.into();
        }
        self
    }

    pub fn help(mut self, text: impl Into<String>) -> Self {
        if let SceneError::At { help, .. } = &mut self {
            *help = Some(text.into());
        }
        self
    }

    pub fn location(&self) -> Option<&Location> {
        match self {
            SceneError::At { location, .. } => Some(location),
            SceneError::Io { .. } => None,
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Io { path, message } => write!(f, "cannot read {}: {message}", path.display()),
            SceneError::At { location, message, .. } => write!(f, "{location}: {message}"),
        }
    }
}

impl std::error::Error for SceneError {}

impl Diagnostic for SceneError {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        None
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        match self {
            SceneError::At { help: Some(h), .. } => Some(Box::new(h)),
            _ => None,
        }
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        match self {
            SceneError::At { location, .. } => Some(&location.file.named as &dyn SourceCode),
            SceneError::Io { .. } => None,
        }
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        match self {
            SceneError::At { location, label, .. } => {
                let len = location.span.len().max(1);
                Some(Box::new(std::iter::once(LabeledSpan::new(
                    Some(label.clone()),
                    location.span.start,
                    len,
                ))))
            }
            SceneError::Io { .. } => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column() {
        let f = SourceFile::new("a.toml", "ab\ncde\n\nf".into());
        assert_eq!(f.line_col(0), (1, 1));
        assert_eq!(f.line_col(4), (2, 2));
        assert_eq!(f.line_col(8), (4, 1));
        let e = SceneError::at(Location::new(&f, 4..5), "bad");
        assert_eq!(e.to_string(), "a.toml:2:2: bad");
    }
}
