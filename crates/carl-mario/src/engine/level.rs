//! Level text → tiles, enemy templates, start and exit (engine_behaviour.md §2).
//!
//! Unlike the oracle (which maps unknown characters to empty space), characters outside the
//! documented alphabet are an error with their line and column: a typo in a user's level file
//! should not silently become air.

use crate::error::{MarioError, Result};

/// Characters the level format defines (§2.2).
pub const KNOWN_TILES: &str = "-MFX#SCUL?@!Q12Do%|*Bb<>[]tTgEGrRkKyY";

/// Enemy type values (§3); also the template of a tile.
pub mod kind {
    pub const GOOMBA: i32 = 2;
    pub const GOOMBA_WINGED: i32 = 3;
    pub const RED_KOOPA: i32 = 4;
    pub const RED_KOOPA_WINGED: i32 = 5;
    pub const GREEN_KOOPA: i32 = 6;
    pub const GREEN_KOOPA_WINGED: i32 = 7;
    pub const SPIKY: i32 = 8;
    pub const SPIKY_WINGED: i32 = 9;
    pub const BULLET_BILL: i32 = 10;
    pub const FLOWER: i32 = 11;
    pub const MUSHROOM: i32 = 12;
    pub const FIRE_FLOWER: i32 = 13;
    pub const SHELL: i32 = 14;
    pub const LIFE_MUSHROOM: i32 = 15;
    pub const FIREBALL: i32 = 16;
    pub const MARIO: i32 = -31;
}

// Tile features (§2.5).
pub const SOLID: u8 = 1;
pub const CANNON: u8 = 2;
pub const BREAKABLE: u8 = 4;
pub const BUMPABLE: u8 = 8;
pub const POWERUP: u8 = 16;
pub const LIFE: u8 = 32;
pub const PICKABLE: u8 = 64;
pub const FROM_ABOVE: u8 = 128;
const FROM_BELOW: u16 = 256;

/// Feature bits of a tile id (u16 because FROM_BELOW needs a ninth bit).
pub fn features(tile: u8) -> u16 {
    let s = SOLID as u16;
    match tile {
        1 | 2 | 4 | 5 | 14 | 18 | 19 | 20 | 21 | 52 | 53 => s,
        3 => s | CANNON as u16,
        6 => s | BREAKABLE as u16,
        7 | 11 => s | BUMPABLE as u16,
        8 | 50 => s | (BUMPABLE | POWERUP) as u16,
        15 => PICKABLE as u16,
        43..=46 => FROM_ABOVE as u16,
        48 => FROM_BELOW | (BUMPABLE | LIFE) as u16,
        49 => FROM_BELOW | BUMPABLE as u16,
        51 => s | (BUMPABLE | LIFE) as u16,
        _ => 0,
    }
}

pub fn has(tile: u8, feature: u8) -> bool {
    features(tile) & feature as u16 != 0
}

/// The level's blocking test for motion `(xa, ya)`.
pub fn blocks_tile(tile: u8, _xa: f32, ya: f32) -> bool {
    let f = features(tile);
    f & SOLID as u16 != 0 || (ya < 0.0 && f & FROM_BELOW != 0) || (ya > 0.0 && f & FROM_ABOVE as u16 != 0)
}

/// A parsed level.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    pub width: usize,
    pub height: usize,
    /// Tile ids, row-major.
    pub tiles: Vec<u8>,
    /// Enemy template (type value) per tile, 0 = none.
    pub templates: Vec<i32>,
    pub start: (i32, i32),
    pub exit: (i32, i32),
}

fn is_solid_char(c: u8) -> bool {
    b"X#@!BCQ<>[]?SUD%tT".contains(&c)
}

fn is_pipe(c: u8) -> bool {
    c == b't' || c == b'T'
}

impl Level {
    /// Parses level text; `origin` names it in error messages.
    pub fn parse(text: &str, origin: &str) -> Result<Level> {
        let mut lines: Vec<&str> = text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l)).collect();
        while lines.last().is_some_and(|l| l.is_empty()) {
            lines.pop();
        }
        let bad = |reason: String| MarioError::BadLevel {
            origin: origin.to_string(),
            reason,
        };
        if lines.is_empty() || lines[0].is_empty() {
            return Err(bad("the level is empty".into()));
        }
        for (y, line) in lines.iter().enumerate() {
            if let Some((x, ch)) = line.chars().enumerate().find(|(_, c)| !KNOWN_TILES.contains(*c)) {
                return Err(MarioError::UnknownTile {
                    origin: origin.to_string(),
                    line: y + 1,
                    column: x + 1,
                    ch,
                });
            }
        }
        let w = lines[0].len();
        if let Some((y, l)) = lines.iter().enumerate().find(|(_, l)| l.len() != w) {
            return Err(bad(format!(
                "line {} has {} characters, line 1 has {w}",
                y + 1,
                l.len()
            )));
        }
        let h = lines.len();
        if w > 4096 || h > 256 {
            return Err(bad(format!("level of {w}×{h} tiles is too large (at most 4096×256)")));
        }
        let ch = |x: usize, y: usize| lines[y].as_bytes()[x];
        let mut tiles = vec![0u8; w * h];
        let mut templates = vec![0i32; w * h];
        let mut start = None;
        let mut exit = None;
        for y in 0..h {
            for x in 0..w {
                let c = ch(x, y);
                let i = y * w + x;
                let (tile, template) = match c {
                    b'M' => {
                        start = Some((x as i32, y as i32));
                        (0, 0)
                    }
                    b'F' => {
                        exit = Some((x as i32, y as i32));
                        (0, 0)
                    }
                    b'X' => (1, 0),
                    b'#' => (2, 0),
                    b'S' => (6, 0),
                    b'C' => (7, 0),
                    b'U' => (50, 0),
                    b'L' => (51, 0),
                    b'?' | b'@' => (8, 0),
                    b'!' | b'Q' => (11, 0),
                    b'1' => (48, 0),
                    b'2' => (49, 0),
                    b'D' => (14, 0),
                    b'o' => (15, 0),
                    b'%' => {
                        let left = x > 0 && ch(x - 1, y) == b'%';
                        let right = x + 1 < w && ch(x + 1, y) == b'%';
                        (43 + 2 * left as u8 + right as u8, 0)
                    }
                    b'|' => (47, 0),
                    b'*' => {
                        let n = (y >= 1 && ch(x, y - 1) == b'*') as u8 + (y >= 2 && ch(x, y - 2) == b'*') as u8;
                        (3 + n, 0)
                    }
                    b'B' => (3, 0),
                    b'b' => (4 + (y >= 2 && ch(x, y - 2) == b'B') as u8, 0),
                    b'<' => (18, 0),
                    b'>' => (19, 0),
                    b'[' => (20, 0),
                    b']' => (21, 0),
                    b't' | b'T' => {
                        let single = x + 1 < w && !is_pipe(ch(x + 1, y)) && x > 0 && !is_pipe(ch(x - 1, y));
                        let mut n = 0u8;
                        if x > 0 && matches!(tiles[i - 1], 18 | 20) {
                            n += 1;
                        }
                        if y > 0 && is_pipe(ch(x, y - 1)) {
                            n += if single { 1 } else { 2 };
                        }
                        let template = if c == b'T' && !single && n == 0 {
                            kind::FLOWER
                        } else {
                            0
                        };
                        (if single { 52 + n } else { 18 + n }, template)
                    }
                    b'g' | b'E' => (0, kind::GOOMBA),
                    b'G' => (0, kind::GOOMBA_WINGED),
                    b'r' => (0, kind::RED_KOOPA),
                    b'R' => (0, kind::RED_KOOPA_WINGED),
                    b'k' => (0, kind::GREEN_KOOPA),
                    b'K' => (0, kind::GREEN_KOOPA_WINGED),
                    b'y' => (0, kind::SPIKY),
                    b'Y' => (0, kind::SPIKY_WINGED),
                    _ => (0, 0),
                };
                tiles[i] = tile;
                templates[i] = template;
            }
        }
        let first_floor = |x: usize| -> i32 {
            let mut seen_solid = false;
            for y in (0..h).rev() {
                let solid = is_solid_char(ch(x, y));
                if solid {
                    seen_solid = true;
                } else if seen_solid {
                    return y as i32;
                }
            }
            -1
        };
        let start = start.unwrap_or_else(|| (0, first_floor(0)));
        let exit = exit.unwrap_or_else(|| (w as i32 - 1, first_floor(w - 1)));
        let (ex, ey) = exit;
        let top = (ey - 11).max(1);
        for yy in top + 1..=ey {
            if (yy as usize) < h {
                tiles[yy as usize * w + ex as usize] = 40;
            }
        }
        if (top as usize) < h {
            tiles[top as usize * w + ex as usize] = 39;
        }
        Ok(Level {
            width: w,
            height: h,
            tiles,
            templates,
            start,
            exit,
        })
    }

    /// Tile at (tx, ty): column clamped into the level, rows outside are empty.
    #[inline]
    pub fn tile(&self, tx: i32, ty: i32) -> u8 {
        if ty < 0 || ty >= self.height as i32 {
            return 0;
        }
        let tx = tx.clamp(0, self.width as i32 - 1);
        self.tiles[ty as usize * self.width + tx as usize]
    }

    /// Sets a tile; outside the level nothing happens.
    pub fn set_tile(&mut self, tx: i32, ty: i32, tile: u8) {
        if tx >= 0 && ty >= 0 && (tx as usize) < self.width && (ty as usize) < self.height {
            self.tiles[ty as usize * self.width + tx as usize] = tile;
        }
    }

    /// Enemy template at (tx, ty) (0 = none or outside).
    pub fn template(&self, tx: i32, ty: i32) -> i32 {
        if tx >= 0 && ty >= 0 && (tx as usize) < self.width && (ty as usize) < self.height {
            self.templates[ty as usize * self.width + tx as usize]
        } else {
            0
        }
    }

    pub fn blocks(&self, tx: i32, ty: i32, xa: f32, ya: f32) -> bool {
        blocks_tile(self.tile(tx, ty), xa, ya)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_tiles_and_ragged_lines_are_located_errors() {
        let e = Level::parse("--X\n-Z-\n", "t").unwrap_err();
        assert!(
            matches!(
                e,
                MarioError::UnknownTile {
                    line: 2,
                    column: 2,
                    ch: 'Z',
                    ..
                }
            ),
            "{e:?}"
        );
        let e = Level::parse("--X\n--\n", "t").unwrap_err();
        assert!(e.to_string().contains("line 2 has 2"), "{e}");
        assert!(Level::parse("\n\n", "t").is_err());
    }

    #[test]
    fn start_exit_and_flag_pole_follow_first_floor() {
        let text = "----\n----\n----\nX--X\nX--X";
        let l = Level::parse(text, "t").unwrap();
        assert_eq!((l.start, l.exit), ((0, 2), (3, 2)));
        assert_eq!(l.tile(3, 1), 39);
        assert_eq!(l.tile(3, 2), 40);
        assert_eq!(l.tile(-5, 3), 1, "columns clamp");
        assert_eq!(l.tile(1, 99), 0);
    }
}
