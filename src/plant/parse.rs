//! The parser of plant files: `grammar/smv.pest` in, [`Model`](super::Model) or a located
//! [`ModelError`](super::ModelError) out. (Being written; nothing calls it yet.)

use super::{Model, ModelError};
use std::path::Path;

/// Reads and resolves a plant file.
pub fn parse_file(path: &Path) -> Result<Model, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    parse_str(&text, path)
}

/// Resolves the text of a plant file.
pub fn parse_str(_text: &str, file: &Path) -> Result<Model, ModelError> {
    Err(ModelError::At {
        file: file.to_path_buf(),
        line: 1,
        column: 1,
        message: "the plant parser is not written yet".into(),
    })
}
