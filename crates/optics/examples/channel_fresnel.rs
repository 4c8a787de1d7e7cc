//! Per-channel Fresnel reflectance of one page of the refractiveindex.info database:
//! `cargo run -p nklut-optics --example channel_fresnel -- 3d/metals/gold`.
use nklut_optics::{
    db::Database,
    fresnel::exact,
    spectrum::{index_at, Channels},
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let page = std::env::args().nth(1).unwrap_or_else(|| "3d/metals/gold".into());
    let db = Database::open(None)?; // refractiveindex/database, or $NKLUT_DB
    let data = db.read_page(&db.catalog()?.find(&page).ok_or("no such page")?.data)?;
    for nm in Channels::default().nanometres() {
        let at = index_at(&data, nm)?;
        let f = [1.0, 0.5, 0.1].map(|cos| exact(at.n, at.k, cos));
        println!("{page} {nm} nm: n {:.4} k {:.4}  F(0°) {:.4} F(60°) {:.4} F(84°) {:.4}", at.n, at.k, f[0], f[1], f[2]);
    }
    Ok(())
}
