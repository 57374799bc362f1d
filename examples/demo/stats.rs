//! Frame-time history and its small graph.

use std::collections::VecDeque;
use std::time::Instant;

use eframe::egui;

/// Window frame times (what a person feels) over the last few seconds.
pub struct FrameClock {
    last: Option<Instant>,
    /// Milliseconds between consecutive window frames, oldest first.
    history: VecDeque<f32>,
}

impl FrameClock {
    const LEN: usize = 180;

    pub fn new() -> Self {
        Self {
            last: None,
            history: VecDeque::with_capacity(Self::LEN),
        }
    }

    /// Records that a window frame began now.
    pub fn tick(&mut self) {
        let now = Instant::now();
        if let Some(last) = self.last {
            if self.history.len() == Self::LEN {
                self.history.pop_front();
            }
            self.history.push_back((now - last).as_secs_f32() * 1e3);
        }
        self.last = Some(now);
    }

    /// Mean frame time over the last second or so, in milliseconds.
    pub fn mean_ms(&self) -> Option<f32> {
        let recent: Vec<f32> = self.history.iter().rev().take(30).copied().collect();
        (!recent.is_empty()).then(|| recent.iter().sum::<f32>() / recent.len() as f32)
    }

    /// Draws the history as a line graph, scaled to its largest value.
    pub fn graph(&self, ui: &mut egui::Ui) {
        let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), 48.0), egui::Sense::hover());
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 2.0, ui.visuals().extreme_bg_color);
        let max = self.history.iter().copied().fold(1.0f32, f32::max);
        let step = rect.width() / (Self::LEN - 1) as f32;
        let points: Vec<egui::Pos2> = self
            .history
            .iter()
            .enumerate()
            .map(|(i, ms)| {
                egui::pos2(
                    rect.left() + i as f32 * step,
                    rect.bottom() - ms / max * rect.height(),
                )
            })
            .collect();
        if points.len() > 1 {
            painter.add(egui::Shape::line(
                points,
                egui::Stroke::new(1.5, egui::Color32::from_rgb(90, 170, 255)),
            ));
        }
        painter.text(
            rect.left_top() + egui::vec2(4.0, 2.0),
            egui::Align2::LEFT_TOP,
            format!("{max:.0} ms"),
            egui::FontId::monospace(10.0),
            ui.visuals().weak_text_color(),
        );
    }
}
