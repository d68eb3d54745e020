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

    /// The mask as a [`MaskView`], which the trace entry points read.
    pub fn view(&self) -> MaskView<'_> {
        MaskView {
            width: self.width,
            height: self.height,
            ink: &self.ink,
        }
    }

    /// Whether pixel `(x, y)` is ink; false outside the image, and for a pixel that `ink` is too
    /// short to hold (the fields are public, so a mask can be built with the wrong length).
    #[inline]
    pub fn get(&self, x: i64, y: i64) -> bool {
        self.view().get(x, y)
    }

    /// Sets pixel `(x, y)` (ignored outside the image, or beyond the end of `ink`).
    #[inline]
    pub fn set(&mut self, x: i64, y: i64, value: bool) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            if let Some(ink) = self
                .ink
                .get_mut(y as usize * self.width as usize + x as usize)
            {
                *ink = value;
            }
        }
    }

    /// Refuses a mask whose `ink` is not `width x height` pixels (the fields are public): the
    /// stages index it by pixel.
    pub(crate) fn check_size(&self) -> crate::error::Result<()> {
        self.view().check_size()
    }

    /// Number of ink pixels.
    pub fn count(&self) -> usize {
        self.view().count()
    }
}

/// A foreground mask borrowed from its owner (a [`Binary`], a numpy bool array): `ink[i]` is
/// true for foreground pixel `i = y * width + x`. [`crate::trace_binary`] reads one in place; a
/// `&Binary` converts into one without copying.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MaskView<'a> {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major foreground flags, `width * height` of them (a trace refuses any other length).
    pub ink: &'a [bool],
}

impl MaskView<'_> {
    /// Whether pixel `(x, y)` is ink; false outside the image, and for a pixel that `ink` is too
    /// short to hold.
    #[inline]
    pub fn get(&self, x: i64, y: i64) -> bool {
        x >= 0
            && y >= 0
            && x < self.width as i64
            && y < self.height as i64
            && self
                .ink
                .get(y as usize * self.width as usize + x as usize)
                .is_some_and(|&ink| ink)
    }

    /// Refuses a mask whose `ink` is not `width x height` pixels: the stages index it by pixel.
    pub(crate) fn check_size(&self) -> crate::error::Result<()> {
        let (width, height) = (self.width as usize, self.height as usize);
        if width.checked_mul(height) != Some(self.ink.len()) {
            return Err(crate::error::Error::InvalidParams(format!(
                "mask has {} pixels for a {width}x{height} image",
                self.ink.len()
            )));
        }
        Ok(())
    }

    /// Number of ink pixels.
    pub fn count(&self) -> usize {
        self.ink.iter().filter(|&&b| b).count()
    }

    /// An owned copy.
    pub fn to_binary(&self) -> Binary {
        Binary {
            width: self.width,
            height: self.height,
            ink: self.ink.to_vec(),
        }
    }
}

impl<'a> From<&'a Binary> for MaskView<'a> {
    fn from(binary: &'a Binary) -> Self {
        binary.view()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mask_with_too_few_flags_reads_as_background_and_ignores_writes() {
        let mut short = Binary {
            width: 4,
            height: 4,
            ink: vec![true; 5],
        };
        assert!(short.get(0, 1));
        assert!(!short.get(3, 3));
        short.set(3, 3, true);
        assert_eq!(short.ink.len(), 5);
        assert!(!short.get(3, 3));
    }
}
