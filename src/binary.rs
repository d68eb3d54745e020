//! The foreground mask: which pixels are ink.

/// A binarized image. `ink[y * width + x]` is true for foreground (stroke) pixels.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Binary {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major foreground flags.
    pub ink: Vec<bool>,
}

impl Binary {
    /// An all-background mask.
    pub fn new(width: u32, height: u32) -> Self {
        Binary {
            width,
            height,
            ink: vec![false; width as usize * height as usize],
        }
    }

    /// Whether pixel `(x, y)` is ink; false outside the image.
    #[inline]
    pub fn get(&self, x: i64, y: i64) -> bool {
        x >= 0
            && y >= 0
            && x < self.width as i64
            && y < self.height as i64
            && self.ink[y as usize * self.width as usize + x as usize]
    }

    /// Sets pixel `(x, y)` (ignored outside the image).
    #[inline]
    pub fn set(&mut self, x: i64, y: i64, value: bool) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            self.ink[y as usize * self.width as usize + x as usize] = value;
        }
    }

    /// Number of ink pixels.
    pub fn count(&self) -> usize {
        self.ink.iter().filter(|&&b| b).count()
    }
}
