//! Regenerate Fairway's sample assets (see `assets/README.md`):
//!
//! ```sh
//! cargo run -p fairway --example make_assets            # writes assets/
//! cargo run -p fairway --example make_assets -- OUT_DIR # writes elsewhere
//! ```

mod generate;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets")));
    std::fs::create_dir_all(&dir)?;
    for (name, text) in generate::generate() {
        let path = dir.join(name);
        fairway::io::write_atomic(&path, text.as_bytes())?;
        println!("wrote {} ({} bytes)", path.display(), text.len());
    }
    Ok(())
}
