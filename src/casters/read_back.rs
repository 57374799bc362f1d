//! A mesh's geometry read back from the engine's GPU buffers, once, for its bounds and smoothed
//! normals (`MeshGeometry::Gpu`), and decoded from the vertex formats penumbra accepts.

use super::desc::index_size;
use super::desc::{IndexStream, VertexStream};
use crate::error::{PenumbraError, Result};
use glam::Vec3;

/// Copies `len` bytes at `offset` of `buffer` back to the CPU.
pub(super) fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    what: &str,
    buffer: &wgpu::Buffer,
    offset: u64,
    len: u64,
) -> Result<Vec<u8>> {
    if !buffer.usage().contains(wgpu::BufferUsages::COPY_SRC) {
        return Err(PenumbraError::input(
            what.to_string(),
            "reading the mesh back needs COPY_SRC usage on its buffers; give the data with MeshGeometry::Cpu instead",
        ));
    }
    let start = offset / 4 * 4;
    let size = (offset + len - start)
        .next_multiple_of(4)
        .min(buffer.size() - start);
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Casters::read_back"),
        size: size.next_multiple_of(4),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("Casters::read_back"),
    });
    encoder.copy_buffer_to_buffer(buffer, start, &staging, 0, size);
    queue.submit([encoder.finish()]);
    let during = format!("reading back {what}");
    crate::error::map_for_reading(device, staging.slice(..), &during)?;
    let gpu = |e: String| PenumbraError::Gpu { during, reason: e };
    let data = staging.get_mapped_range(..).map_err(|e| gpu(e.to_string()))?;
    let skip = (offset - start) as usize;
    Ok(data[skip..skip + len as usize].to_vec())
}

/// The bytes of `count` vertices of a stream, stride included.
pub(super) fn read_stream(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    what: &str,
    name: &str,
    s: &VertexStream,
    count: u32,
) -> Result<Vec<u8>> {
    if count == 0 {
        return Ok(Vec::new());
    }
    let len = s.stride * (count as u64 - 1) + s.format.size();
    read_buffer(device, queue, &format!("{what} {name}"), s.buffer, s.offset, len)
}

pub(super) fn read_indices(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    what: &str,
    ix: &IndexStream,
) -> Result<Vec<u32>> {
    let size = index_size(ix.format);
    let bytes = read_buffer(
        device,
        queue,
        &format!("{what} indices"),
        ix.buffer,
        ix.offset,
        ix.count as u64 * size,
    )?;
    Ok(match ix.format {
        wgpu::IndexFormat::Uint16 => bytes
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]) as u32)
            .collect(),
        wgpu::IndexFormat::Uint32 => bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect(),
    })
}

/// Decodes the first three components of each vertex of a stream read back with its stride.
pub(super) fn decode_vec3(bytes: &[u8], s: &VertexStream) -> Vec<Vec3> {
    let stride = s.stride as usize;
    let count = if bytes.is_empty() {
        0
    } else {
        (bytes.len() - s.format.size() as usize) / stride + 1
    };
    (0..count)
        .map(|i| {
            let b = &bytes[i * stride..];
            let f32_at = |k: usize| f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]);
            let u16_at = |k: usize| u16::from_le_bytes([b[2 * k], b[2 * k + 1]]);
            match s.format {
                wgpu::VertexFormat::Float16x4 => Vec3::new(
                    f16_to_f32(u16_at(0)),
                    f16_to_f32(u16_at(1)),
                    f16_to_f32(u16_at(2)),
                ),
                wgpu::VertexFormat::Snorm8x4 => Vec3::new(snorm8(b[0]), snorm8(b[1]), snorm8(b[2])),
                wgpu::VertexFormat::Snorm16x4 => {
                    Vec3::new(snorm16(u16_at(0)), snorm16(u16_at(1)), snorm16(u16_at(2)))
                }
                _ => Vec3::new(f32_at(0), f32_at(1), f32_at(2)),
            }
        })
        .collect()
}

fn snorm8(b: u8) -> f32 {
    (b as i8 as f32 / 127.0).max(-1.0)
}

fn snorm16(v: u16) -> f32 {
    (v as i16 as f32 / 32767.0).max(-1.0)
}

/// IEEE half to single precision.
fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = ((h >> 10) & 0x1f) as i32;
    let mantissa = (h & 0x3ff) as f32;
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 => {
            if mantissa == 0.0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_decode() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x3800), 0.5);
        assert_eq!(f16_to_f32(0x0000), 0.0);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!((f16_to_f32(0x0001) - 5.96e-8).abs() < 1e-9);
    }

    #[test]
    fn snorm_decodes_to_unit_range() {
        assert_eq!(snorm8(127), 1.0);
        assert_eq!(snorm8(0x81), -1.0);
        assert_eq!(snorm8(0x80), -1.0);
        assert_eq!(snorm16(0), 0.0);
    }
}
