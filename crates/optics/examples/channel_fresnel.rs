//! Per-channel Fresnel reflectance of one page of the refractiveindex.info database:
//! `cargo run -p nklut-optics --example channel_fresnel -- 3d/metals/gold`, with the database
//! at `refractiveindex/database` or where `$NKLUT_DB` says.
use nklut_optics::{
    db::{Database, DEFAULT_DB},
    fresnel::exact,
    spectrum::{index_at, Channels},
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let page = std::env::args().nth(1).unwrap_or_else(|| "3d/metals/gold".into());
    // The library reads no environment variable: the program decides where the database is.
    let dir = std::env::var_os("NKLUT_DB").map(std::path::PathBuf::from).unwrap_or_else(|| DEFAULT_DB.into());
    let db = Database::open(&dir)?;
    let data = db.read_page(&db.catalog()?.find(&page).ok_or("no such page")?.data)?;
    for nm in Channels::default().nanometres() {
        let at = index_at(&data, nm)?;
        let f = [1.0, 0.5, 0.1].map(|cos| exact(at.n, at.k, cos));
        println!("{page} {nm} nm: n {:.4} k {:.4}  F(0°) {:.4} F(60°) {:.4} F(84°) {:.4}", at.n, at.k, f[0], f[1], f[2]);
    }
    Ok(())
}
