//! Puts the 3D views of two viewer screenshots side by side in one PNG, for
//! docs/sdf.md (`scripts/sdf-pictures.sh`): each image loses its first
//! `PANEL` columns (the side panel), and colours are rounded to multiples of
//! 8 per channel, which keeps the smooth slices small as PNG.
//!
//! ```text
//! cargo run --release -p proxima-viewer --example side_by_side -- PANEL LEFT.png RIGHT.png OUT.png
//! ```

use image::{GenericImage, RgbImage};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [panel, left, right, out] = args.as_slice() else {
        return Err("usage: side_by_side PANEL LEFT.png RIGHT.png OUT.png".into());
    };
    let panel: u32 = panel.parse()?;
    let views: Vec<RgbImage> = [left, right]
        .iter()
        .map(|path| -> Result<RgbImage, Box<dyn std::error::Error>> {
            let image = image::open(path)?.to_rgb8();
            let width = image
                .width()
                .checked_sub(panel)
                .ok_or("the panel is wider than the image")?;
            Ok(image::imageops::crop_imm(&image, panel, 0, width, image.height()).to_image())
        })
        .collect::<Result<_, _>>()?;
    let width = views.iter().map(|v| v.width()).sum();
    let height = views.iter().map(|v| v.height()).max().unwrap_or(0);
    let mut joined = RgbImage::new(width, height);
    let mut x = 0;
    for view in &views {
        joined.copy_from(view, x, 0)?;
        x += view.width();
    }
    for pixel in joined.pixels_mut() {
        pixel.0 = pixel.0.map(|c| (c & !7) | (c >> 5));
    }
    joined.save(out)?;
    Ok(())
}
