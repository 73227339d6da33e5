//! Frames to file bytes: PNG (one frame) or an animated GIF. Both encoders are pure Rust and
//! pinned exactly in `Cargo.toml`, so the same frames give the same bytes on every machine.

use super::frame::Frame;

/// One frame as PNG bytes (8-bit RGB) with the given `tEXt` chunks (keyword, text), in order.
pub fn png_bytes(frame: &Frame, text: &[(&str, &str)]) -> Result<Vec<u8>, String> {
    let expected = 3 * frame.width as usize * frame.height as usize;
    if frame.rgb.len() != expected {
        return Err(format!(
            "a {}x{} frame needs {expected} bytes, not {}",
            frame.width,
            frame.height,
            frame.rgb.len()
        ));
    }
    let err = |e: png::EncodingError| format!("PNG encoding failed: {e}");
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, frame.width, frame.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        for (key, value) in text {
            enc.add_text_chunk(key.to_string(), value.to_string()).map_err(err)?;
        }
        let mut w = enc.write_header().map_err(err)?;
        w.write_image_data(&frame.rgb).map_err(err)?;
        w.finish().map_err(err)?;
    }
    Ok(bytes)
}

/// Frames as an endlessly looping GIF, `delay_cs` hundredths of a second per frame. Colours
/// are reduced to each frame's own 256-colour palette (NeuQuant, speed 30: the flat colours of
/// these scenes need no more).
pub fn gif_bytes(frames: &[Frame], delay_cs: u16) -> Result<Vec<u8>, String> {
    let Some(first) = frames.first() else {
        return Err("a GIF needs at least one frame".into());
    };
    let (w, h) = (
        u16::try_from(first.width).map_err(|_| "frame too wide for GIF")?,
        u16::try_from(first.height).map_err(|_| "frame too tall for GIF")?,
    );
    let mut bytes = Vec::new();
    {
        let err = |e: gif::EncodingError| format!("GIF encoding failed: {e}");
        let mut enc = gif::Encoder::new(&mut bytes, w, h, &[]).map_err(err)?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(err)?;
        for f in frames {
            if (f.width, f.height) != (first.width, first.height) {
                return Err(format!(
                    "all GIF frames must have one size: {}x{} then {}x{}",
                    first.width, first.height, f.width, f.height
                ));
            }
            let mut g = gif::Frame::from_rgb_speed(w, h, &f.rgb, 30);
            g.delay = delay_cs;
            enc.write_frame(&g).map_err(err)?;
        }
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker(w: u32, h: u32) -> Frame {
        let mut rgb = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let v = if (x / 4 + y / 4) % 2 == 0 { 255 } else { 0 };
                rgb.extend_from_slice(&[v, 128, 255 - v]);
            }
        }
        Frame {
            width: w,
            height: h,
            rgb,
        }
    }

    #[test]
    fn png_round_trips_pixels_and_text() {
        let f = checker(16, 8);
        let bytes = png_bytes(&f, &[("Title", "t"), ("Software", "s")]).unwrap();
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut r = dec.read_info().unwrap();
        let chunks: Vec<(String, String)> = r
            .info()
            .uncompressed_latin1_text
            .iter()
            .map(|c| (c.keyword.clone(), c.text.clone()))
            .collect();
        assert_eq!(chunks, [("Title".into(), "t".into()), ("Software".into(), "s".into())]);
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (16, 8));
        assert_eq!(&buf[..info.buffer_size()], &f.rgb[..]);
        let short = Frame {
            rgb: vec![0; 5],
            ..checker(2, 2)
        };
        assert!(png_bytes(&short, &[]).is_err());
    }

    #[test]
    fn gif_has_all_frames_and_rejects_mixed_sizes() {
        let frames = vec![checker(8, 8), checker(8, 8), checker(8, 8)];
        let bytes = gif_bytes(&frames, 5).unwrap();
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::RGBA);
        let mut d = opts.read_info(std::io::Cursor::new(bytes)).unwrap();
        let mut n = 0;
        while let Some(fr) = d.read_next_frame().unwrap() {
            assert_eq!(fr.delay, 5);
            n += 1;
        }
        assert_eq!(n, 3);
        assert!(gif_bytes(&[checker(8, 8), checker(4, 8)], 5).is_err());
        assert!(gif_bytes(&[], 5).is_err());
    }
}
