//! carl-spec's own neutral art for the Mario world: flat tiles and box sprites in its own palette
//! (no Nintendo-derived sprites). The 256×256 frame is what `render` shows; observations sample
//! it nearest-neighbour (OpenCV `INTER_NEAREST`: source index `floor(i·256/dim)`) and convert to
//! grayscale with the ITU-R 601 weights, like CARL's `cv2.cvtColor(RGB2GRAY)` + `cv2.resize`.

use crate::engine::World;
use crate::engine::level::kind;

/// Side of the square screen in pixels.
pub const SCREEN: usize = 256;

const SKY: [u8; 3] = [120, 170, 235];

fn tile_colour(tile: u8, u: i32, v: i32) -> Option<[u8; 3]> {
    let border = u == 0 || v == 0 || u == 15 || v == 15;
    Some(match tile {
        1 => {
            if v % 8 == 0 || (u % 8 == 0) {
                [110, 60, 30]
            } else {
                [150, 90, 45]
            }
        }
        2 => {
            if border {
                [90, 60, 40]
            } else {
                [170, 120, 80]
            }
        }
        3..=5 => {
            if (2..=13).contains(&u) {
                [70, 70, 75]
            } else {
                [30, 30, 30]
            }
        }
        6 | 7 | 50 | 51 => {
            let offset = if (v / 8) % 2 == 0 { 0 } else { 8 };
            if v % 8 == 0 || (u + offset) % 16 == 0 {
                [90, 40, 20]
            } else {
                [190, 90, 50]
            }
        }
        8 | 11 => {
            if border {
                [120, 80, 10]
            } else if (6..10).contains(&u) && (4..12).contains(&v) {
                [255, 250, 210]
            } else {
                [235, 185, 40]
            }
        }
        14 => {
            if border {
                [70, 45, 30]
            } else {
                [125, 90, 60]
            }
        }
        15 => {
            let (du, dv) = (2 * u - 15, 2 * v - 15);
            if du * du * 4 + dv * dv * 2 < 14 * 14 * 2 {
                [250, 210, 40]
            } else {
                return None;
            }
        }
        18..=21 | 52 | 53 => {
            let edge = !(2..=13).contains(&u) || (matches!(tile, 18 | 19 | 52) && v < 2);
            if edge { [20, 100, 20] } else { [60, 180, 60] }
        }
        39 => {
            let (du, dv) = (u - 8, v - 8);
            if du * du + dv * dv < 20 {
                [240, 240, 240]
            } else {
                return None;
            }
        }
        40 if (7..9).contains(&u) => [200, 200, 200],
        43..=46 if v < 6 => [220, 170, 90],
        47 if (5..11).contains(&u) => [205, 185, 150],
        _ => return None,
    })
}

fn sprite_colour(world: &World, id: usize) -> [u8; 3] {
    let s = &world.sprites[id];
    match s.kind {
        kind::MARIO => {
            if world.mario.is_fire {
                [250, 250, 250]
            } else if world.mario.is_large {
                [200, 30, 30]
            } else {
                [230, 60, 60]
            }
        }
        kind::GOOMBA | kind::GOOMBA_WINGED => [120, 70, 30],
        kind::RED_KOOPA | kind::RED_KOOPA_WINGED => [210, 50, 40],
        kind::GREEN_KOOPA | kind::GREEN_KOOPA_WINGED => [40, 150, 40],
        kind::SPIKY | kind::SPIKY_WINGED => [160, 20, 60],
        kind::BULLET_BILL => [15, 15, 15],
        kind::FLOWER => [30, 120, 30],
        kind::MUSHROOM => [240, 120, 60],
        kind::LIFE_MUSHROOM => [90, 220, 90],
        kind::FIRE_FLOWER => [255, 150, 0],
        kind::SHELL => [70, 130, 90],
        kind::FIREBALL => [255, 200, 40],
        _ => [255, 0, 255],
    }
}

/// The sprites' boxes in world pixels with their colours, drawing order (Mario last, on top).
struct Scene<'a> {
    world: &'a World,
    boxes: Vec<([i32; 4], [u8; 3])>,
}

impl<'a> Scene<'a> {
    fn new(world: &'a World) -> Self {
        let mut ids: Vec<usize> = world.list.iter().copied().filter(|&id| id != 0).collect();
        if world.list.contains(&0) {
            ids.push(0);
        }
        let boxes = ids
            .into_iter()
            .map(|id| {
                let s = &world.sprites[id];
                (
                    [s.x as i32 - s.w, s.y as i32 - s.h, s.x as i32 + s.w, s.y as i32],
                    sprite_colour(world, id),
                )
            })
            .collect();
        Scene { world, boxes }
    }

    /// Draws screen row `sy` at the screen columns `xs` into `out` via `put(index, colour)`.
    /// Only the sprites crossing the row are tested per pixel.
    fn row(&self, sy: i32, xs: impl Iterator<Item = i32>, mut put: impl FnMut(usize, [u8; 3])) {
        let w = self.world;
        let (cx, wy) = (w.cam_x as i32, sy + w.cam_y as i32);
        let boxes: Vec<&([i32; 4], [u8; 3])> = self
            .boxes
            .iter()
            .filter(|([_, y0, _, y1], _)| wy >= *y0 && wy < *y1)
            .collect();
        let (ty, v) = (wy.div_euclid(16), wy.rem_euclid(16));
        for (i, sx) in xs.enumerate() {
            let wx = sx + cx;
            let sprite = boxes.iter().rev().find(|([x0, _, x1, _], _)| wx >= *x0 && wx < *x1);
            let colour = match sprite {
                Some((_, c)) => *c,
                None => {
                    let tx = wx.div_euclid(16);
                    let tile = if tx >= 0 && (tx as usize) < w.level.width {
                        w.level.tile(tx, ty)
                    } else {
                        0
                    };
                    tile_colour(tile, wx.rem_euclid(16), v).unwrap_or(SKY)
                }
            };
            put(i, colour);
        }
    }
}

/// The 256×256 RGB frame, row-major.
pub fn frame_rgb(world: &World) -> Vec<u8> {
    let scene = Scene::new(world);
    let mut out = vec![0u8; SCREEN * SCREEN * 3];
    for (sy, row) in out.chunks_exact_mut(SCREEN * 3).enumerate() {
        scene.row(sy as i32, 0..SCREEN as i32, |i, c| {
            row[3 * i..3 * i + 3].copy_from_slice(&c)
        });
    }
    out
}

/// ITU-R 601 luma, rounded (OpenCV's RGB2GRAY weights).
pub fn gray([r, g, b]: [u8; 3]) -> u8 {
    ((299 * r as u32 + 587 * g as u32 + 114 * b as u32 + 500) / 1000) as u8
}

/// The grayscale frame downsampled to `dim`×`dim` (nearest neighbour), into `out`.
pub fn observe_gray(world: &World, dim: usize, out: &mut [u8]) {
    debug_assert_eq!(out.len(), dim * dim, "observation buffer");
    let scene = Scene::new(world);
    for (r, row) in out.chunks_exact_mut(dim).enumerate() {
        let sy = (r * SCREEN / dim) as i32;
        scene.row(sy, (0..dim).map(|c| (c * SCREEN / dim) as i32), |i, c| row[i] = gray(c));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::{Buttons, Level};

    #[test]
    fn frame_shows_ground_sky_and_mario() {
        let rows: Vec<String> = (0..16).map(|y| if y < 14 { "-" } else { "X" }.repeat(20)).collect();
        let mut w = World::new(Level::parse(&rows.join("\n"), "t").unwrap(), 100, 0.89, false, false);
        w.tick(Buttons::default());
        let f = frame_rgb(&w);
        let px = |x: usize, y: usize| [f[3 * (y * 256 + x)], f[3 * (y * 256 + x) + 1], f[3 * (y * 256 + x) + 2]];
        assert_eq!(px(100, 10), SKY);
        assert_eq!(px(100, 250), [150, 90, 45], "ground fill");
        let m = w.mario();
        assert_eq!(px(m.x as usize, m.y as usize - 2), [230, 60, 60], "small Mario");
        let mut obs = vec![0u8; 64 * 64];
        observe_gray(&w, 64, &mut obs);
        for r in 0..64 {
            for c in 0..64 {
                assert_eq!(
                    obs[r * 64 + c],
                    gray(px(4 * c, 4 * r)),
                    "nearest neighbour at ({r}, {c})"
                );
            }
        }
        assert_eq!(obs[0], gray(SKY));
    }
}
