//! Plotting setup shared by the tools that draw PNG plots (the simulated
//! machine's run plot; later the latency test and the scope): plotters'
//! bitmap backend with text drawn from a built-in bitmap font
//! ([`font`]), so plotting needs no font files, no fontconfig and no
//! freetype on the machine.
//!
//! ```no_run
//! use hal_scope::plot::png;
//! use plotters::prelude::*;
//! let root = png("out.png", (800, 600)).into_drawing_area();
//! root.fill(&WHITE).unwrap();
//! let mut chart = ChartBuilder::on(&root)
//!     .caption("speed", ("sans-serif", 20))
//!     .x_label_area_size(30)
//!     .y_label_area_size(50)
//!     .build_cartesian_2d(0.0..1.0, 0.0..1.0)
//!     .unwrap();
//! chart.configure_mesh().draw().unwrap();
//! root.present().unwrap();
//! ```

pub mod font;

use plotters::prelude::BitMapBackend;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// A drawing backend that draws text with the built-in font and passes
/// everything else to `B`.
pub struct GlyphText<B> {
    inner: B,
}

/// A PNG file of `size` pixels at `path`, with the built-in font
/// (written on `present`).
pub fn png(path: &str, size: (u32, u32)) -> GlyphText<BitMapBackend<'_>> {
    GlyphText {
        inner: BitMapBackend::new(path, size),
    }
}

/// Font pixels per bitmap pixel for a text of `size` (plotters' size in
/// pixels): the 7-pixel glyphs at about the size asked for.
fn zoom(size: f64) -> i32 {
    ((size / 9.0).round() as i32).max(1)
}

impl<B: DrawingBackend> DrawingBackend for GlyphText<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let z = zoom(style.size());
        let n = text.chars().count() as i32;
        let w = (n * font::ADVANCE - 1).max(0) * z;
        Ok((w as u32, (font::GLYPH_H * z) as u32))
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        use plotters_backend::text_anchor::{HPos, VPos};
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let z = zoom(style.size());
        let (w, h) = self.estimate_text_size(text, style)?;
        let (w, h) = (w as i32, h as i32);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -w,
            HPos::Center => -w / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -h / 2,
            VPos::Bottom => -h,
        };
        let trans = style.transform();
        let (sw, sh) = self.get_size();
        for (fx, fy) in font::pixels(text) {
            for (ox, oy) in (0..z).flat_map(|a| (0..z).map(move |b| (a, b))) {
                let (x, y) = trans.transform(fx * z + ox + dx, fy * z + oy + dy);
                let (x, y) = (pos.0 + x, pos.1 + y);
                if x >= 0 && x < sw as i32 && y >= 0 && y < sh as i32 {
                    self.inner.draw_pixel((x, y), color)?;
                }
            }
        }
        Ok(())
    }
}
