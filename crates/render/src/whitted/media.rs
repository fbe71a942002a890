//! Nested media: the stack of transparent solids a ray is inside, so that the index of
//! refraction on each side of an interface is known (glass inside water, air bubbles in
//! glass). Fixed size and `Copy`: no allocation per ray.
//!
//! Overlaps follow POV-Ray 3.7's rules (`Trace::ComputeRefraction`): leaving a solid
//! that is not the innermost one is treated as an interface of index ratio 1.

/// Deepest nesting tracked; beyond it, further solids are refracted as if entered
/// from the current medium but not remembered.
const MAX_NESTING: usize = 8;

/// Unused slots always hold `(0, 1.0)`, so equal stacks compare equal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MediaStack {
    len: u8,
    objects: [u32; MAX_NESTING],
    iors: [f32; MAX_NESTING],
}

impl MediaStack {
    /// Outside every object (in air, index 1).
    pub const EMPTY: MediaStack = MediaStack {
        len: 0,
        objects: [0; MAX_NESTING],
        iors: [1.0; MAX_NESTING],
    };

    /// Index of refraction of the medium the ray travels in.
    #[inline]
    pub fn current_ior(&self) -> f32 {
        if self.len == 0 {
            1.0
        } else {
            self.iors[self.len as usize - 1]
        }
    }

    #[cfg(test)]
    pub fn depth(&self) -> usize {
        self.len as usize
    }

    /// Crossing the surface of `object` (index `ior`), `entering` it or leaving it.
    /// Returns `eta = n1 / n2` for Snell's law and the stack on the far side.
    pub fn cross(&self, object: u32, ior: f32, entering: bool) -> (f32, MediaStack) {
        let mut next = *self;
        let n = self.len as usize;
        if entering {
            let n1 = self.current_ior();
            if n < MAX_NESTING {
                next.objects[n] = object;
                next.iors[n] = ior;
                next.len += 1;
            }
            return (n1 / ior, next);
        }
        match self.objects[..n].iter().rposition(|&o| o == object) {
            Some(i) if i + 1 == n => {
                next.len -= 1;
                next.objects[i] = 0;
                next.iors[i] = 1.0;
                (ior / next.current_ior(), next)
            }
            Some(i) => {
                // Leaving an overlap with an outer object: remove it, no bending.
                next.objects.copy_within(i + 1..n, i);
                next.iors.copy_within(i + 1..n, i);
                next.len -= 1;
                next.objects[n - 1] = 0;
                next.iors[n - 1] = 1.0;
                (1.0, next)
            }
            // Leaving a solid the ray was never seen entering (the camera is inside).
            None => (ior / self.current_ior(), next),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_glass_and_water() {
        let air = MediaStack::EMPTY;
        let (eta, in_glass) = air.cross(1, 1.5, true);
        assert_eq!(eta, 1.0 / 1.5);
        let (eta, in_water) = in_glass.cross(2, 1.33, true);
        assert_eq!(eta, 1.5 / 1.33);
        assert_eq!(in_water.current_ior(), 1.33);
        let (eta, back_in_glass) = in_water.cross(2, 1.33, false);
        assert_eq!(eta, 1.33 / 1.5);
        assert_eq!(back_in_glass, in_glass);
        let (eta, out) = back_in_glass.cross(1, 1.5, false);
        assert_eq!(eta, 1.5);
        assert_eq!(out.depth(), 0);
    }

    #[test]
    fn leaving_an_outer_overlapping_solid_does_not_bend() {
        let (_, a) = MediaStack::EMPTY.cross(1, 1.5, true);
        let (_, ab) = a.cross(2, 1.2, true);
        let (eta, b) = ab.cross(1, 1.5, false);
        assert_eq!(eta, 1.0);
        assert_eq!(b.current_ior(), 1.2);
        assert_eq!(b.depth(), 1);
    }
}
