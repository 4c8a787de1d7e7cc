//! What several benchmarks share: the distinct materials of the whole database.

use std::sync::Arc;

use nklut::ingest::{distinct_materials, ingest, Selection};
use nklut::spectrum::Material;

/// Every distinct material of the database (pages sharing a data file counted once).
pub fn materials() -> Vec<Arc<Material>> {
    let db = nklut::open_database(None).expect("the database must be linked: run `make db`");
    let all = ingest(&db, &Selection::All, &nklut::ingest::Config::default()).expect("ingest");
    distinct_materials(&all.kept).0
}
