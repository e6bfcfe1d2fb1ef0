//! The payload of a checkpoint of a run that remeshes: the plain run's ([`Payload`]: the
//! integrator's state, the history rows, the field frames), then what the remeshings made and
//! the run stands on ([`crate::remesh::RemeshCheckpoint`]): the problem over the current mesh
//! ([`super::problem`]), the records ([`super::remeshings`]), the distortion that triggers the
//! next remeshing, the time step the stable limit forced since the last one, and what the
//! watches hold. Every `f64` as its raw bits.

use super::bytes::{Read, Reader, Short, Writer};
use super::payload::{OutputMarks, Payload};
use super::problem::{read_problem, write_problem};
use super::remeshings::{read_remeshings, write_remeshings};
use crate::problem::Problem;
use crate::remesh::{NearTipMarks, NearTipRow, RemeshCheckpoint, RemeshStart, WatchMarks};

/// The bytes of the checkpoint `at`, with the field frames listed so far.
pub fn encode(at: RemeshCheckpoint<'_>, frames: Vec<(f64, String)>) -> Vec<u8> {
    let RemeshCheckpoint {
        problem,
        records,
        threshold,
        step_now,
        state,
        columns,
        rows,
        watches,
    } = at;
    let plain = Payload {
        state,
        marks: OutputMarks {
            columns: columns.to_vec(),
            rows: rows.to_vec(),
            frames,
        },
    }
    .encode();
    let mut w = Writer::default();
    w.usize(plain.len());
    w.bytes.extend_from_slice(&plain);
    w.bool(problem.is_some());
    if let Some(p) = problem {
        write_problem(&mut w, p);
    }
    write_remeshings(&mut w, records);
    w.f64(threshold);
    w.opt_f64(step_now);
    let WatchMarks { near_tip } = watches;
    w.bool(near_tip.is_some());
    if let Some(NearTipMarks {
        lines,
        recent,
        after,
    }) = near_tip
    {
        w.usize(lines.len());
        lines.iter().for_each(|l| w.str(l));
        w.usize(recent.len());
        for row in recent {
            let NearTipRow {
                step,
                time,
                elements,
                max_von_mises,
                mean_von_mises,
                mean_pressure,
            } = row;
            w.usize(step);
            w.f64(time);
            w.usize(elements);
            for v in [max_von_mises, mean_von_mises, mean_pressure] {
                w.f64(v);
            }
        }
        w.usize(after);
    }
    w.bytes
}

/// Reads what [`encode`] wrote, the problem onto `scene` (the problem the scene builds):
/// where the run goes on from, and the field frames listed. Every byte must be used.
pub fn decode(bytes: &[u8], scene: &Problem) -> Read<(RemeshStart, Vec<(f64, String)>)> {
    let mut r = Reader::new(bytes);
    let n = r.usize("plain payload length")?;
    let Payload { state, marks } = Payload::decode(r.part(n, "plain payload")?)?;
    let problem = if r.bool("problem present")? {
        Some(read_problem(&mut r, scene)?)
    } else {
        None
    };
    let records = read_remeshings(&mut r)?;
    let threshold = r.f64("remeshing threshold")?;
    let step_now = r.opt_f64("time step since the last remeshing")?;
    let near_tip = if r.bool("near-tip marks present")? {
        let lines = (0..r.usize("near-tip line count")?)
            .map(|_| r.str("near-tip line"))
            .collect::<Read<Vec<_>>>()?;
        let recent = (0..r.usize("near-tip row count")?)
            .map(|_| {
                let what = "near-tip row";
                Ok(NearTipRow {
                    step: r.usize(what)?,
                    time: r.f64(what)?,
                    elements: r.usize(what)?,
                    max_von_mises: r.f64(what)?,
                    mean_von_mises: r.f64(what)?,
                    mean_pressure: r.f64(what)?,
                })
            })
            .collect::<Read<Vec<_>>>()?;
        let after = r.usize("near-tip steps after")?;
        Some(NearTipMarks {
            lines,
            recent,
            after,
        })
    } else {
        None
    };
    if r.remaining() != 0 {
        return Err(Short(format!(
            "{} bytes after the payload's end",
            r.remaining()
        )));
    }
    let OutputMarks {
        columns,
        rows,
        frames,
    } = marks;
    Ok((
        RemeshStart {
            problem,
            records,
            threshold,
            step_now,
            state,
            columns,
            rows,
            watches: WatchMarks { near_tip },
        },
        frames,
    ))
}
