//! The parser of plant files: `grammar/smv.pest` in, [`Model`](super::Model) or a located
//! [`ModelError`](super::ModelError) out. (Being written; nothing calls it yet.)
