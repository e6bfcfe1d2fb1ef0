//! The checkpoint's payload: the integrator's state between two steps ([`RestartState`]), the
//! history rows written so far (so that the history CSV is rebuilt exactly, whatever was
//! flushed before a kill) and the field frames listed in the collection. Every `f64` and `f32`
//! is stored as its raw bits. The structs are taken apart field by field without `..`, so a
//! field added to one of them fails to compile here until the format carries it (and
//! [`super::file::FORMAT_VERSION`] is raised).

use super::bytes::{Read, Reader, Short, Writer};
use crate::dynamics::{ContactTotals, EnergyLedger, RestartState, ScheduleRecord, StopProgress};
use crate::model::{BodyHistory, MaterialHistory};

/// What the output observers have written when the checkpoint is taken.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct OutputMarks {
    /// The history CSV's columns.
    pub columns: Vec<String>,
    /// Every history row written so far, in order.
    pub rows: Vec<Vec<f64>>,
    /// Time and file name of every field frame listed in the collection so far.
    pub frames: Vec<(f64, String)>,
}

/// One checkpoint's content.
#[derive(Debug, Clone, PartialEq)]
pub struct Payload {
    /// The integrator's state.
    pub state: RestartState,
    /// What the output holds.
    pub marks: OutputMarks,
}

fn energies(w: &mut Writer, e: &EnergyLedger) {
    let EnergyLedger {
        kinetic,
        initial_kinetic,
        internal_work,
        external_work,
        damping_work,
        contact_work,
        friction_work,
        history_work,
        remesh_work,
    } = *e;
    for v in [
        kinetic,
        initial_kinetic,
        internal_work,
        external_work,
        damping_work,
        contact_work,
        friction_work,
        history_work,
        remesh_work,
    ] {
        w.f64(v);
    }
}

fn read_energies(r: &mut Reader) -> Read<EnergyLedger> {
    let mut f = || r.f64("energy ledger");
    Ok(EnergyLedger {
        kinetic: f()?,
        initial_kinetic: f()?,
        internal_work: f()?,
        external_work: f()?,
        damping_work: f()?,
        contact_work: f()?,
        friction_work: f()?,
        history_work: f()?,
        remesh_work: f()?,
    })
}

fn history(w: &mut Writer, h: &MaterialHistory) {
    w.usize(h.bodies.len());
    for body in &h.bodies {
        w.bool(body.is_some());
        if let Some(BodyHistory {
            state_len,
            values,
            cauchy,
            ..
        }) = body
        {
            w.usize(*state_len);
            w.f32s(values);
            let flat: Vec<f64> = cauchy.iter().flatten().copied().collect();
            w.f64s(&flat);
        }
    }
}

fn read_history(r: &mut Reader) -> Read<MaterialHistory> {
    let n = r.usize("body count")?;
    let mut bodies = Vec::new();
    for _ in 0..n {
        if !r.bool("body history present")? {
            bodies.push(None);
            continue;
        }
        let state_len = r.usize("history length")?;
        let values = r.f32s("history values")?;
        let flat = r.f64s("element stresses")?;
        if flat.len() % 6 != 0 {
            return Err(Short("element stresses: not six per element".into()));
        }
        let cauchy = flat
            .chunks_exact(6)
            .map(|c| [c[0], c[1], c[2], c[3], c[4], c[5]])
            .collect();
        // Which elements the values belong to is the reader's to set (a rank's part starts at
        // its range, `dynamics::explicit::rank_restart`).
        bodies.push(Some(BodyHistory {
            state_len,
            first: 0,
            values,
            cauchy,
        }));
    }
    Ok(MaterialHistory { bodies })
}

fn schedule(w: &mut Writer, s: &ScheduleRecord) {
    let ScheduleRecord {
        next_history,
        next_field,
        next_snapshot,
        max_scale,
        max_abs_error,
        flags,
        steps,
        stop,
    } = *s;
    for v in [
        next_history,
        next_field,
        next_snapshot,
        max_scale,
        max_abs_error,
    ] {
        w.f64(v);
    }
    w.usize(flags);
    w.usize(steps);
    let (started_below, reached_at) = stop.parts();
    w.bool(started_below.is_some());
    w.bool(started_below == Some(true));
    w.opt_f64(reached_at);
}

fn read_schedule(r: &mut Reader) -> Read<ScheduleRecord> {
    let what = "output schedule";
    let next_history = r.f64(what)?;
    let next_field = r.f64(what)?;
    let next_snapshot = r.f64(what)?;
    let max_scale = r.f64(what)?;
    let max_abs_error = r.f64(what)?;
    let flags = r.usize(what)?;
    let steps = r.usize(what)?;
    let has_side = r.bool(what)?;
    let below = r.bool(what)?;
    let reached_at = r.opt_f64(what)?;
    Ok(ScheduleRecord {
        next_history,
        next_field,
        next_snapshot,
        max_scale,
        max_abs_error,
        flags,
        steps,
        stop: StopProgress::from_parts(has_side.then_some(below), reached_at),
    })
}

impl Payload {
    /// The payload's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let mut w = Writer::default();
        let RestartState {
            u,
            v_half,
            v_full,
            du_prev,
            reaction,
            step,
            time,
            time_step,
            step_origin,
            time_origin,
            dt_before_resume,
            energies: e,
            pending,
            history: h,
            contact_totals,
            schedule: s,
        } = &self.state;
        for v in [u, v_half, v_full, du_prev, reaction] {
            w.vectors(v);
        }
        w.usize(*step);
        w.f64(*time);
        w.f64(*time_step);
        w.usize(*step_origin);
        w.f64(*time_origin);
        w.opt_f64(*dt_before_resume);
        energies(&mut w, e);
        energies(&mut w, pending);
        history(&mut w, h);
        let ContactTotals {
            steps_with_contact,
            solves,
            not_converged,
            unresolved,
            iterations,
        } = *contact_totals;
        for v in [
            steps_with_contact,
            solves,
            not_converged,
            unresolved,
            iterations,
        ] {
            w.usize(v);
        }
        schedule(&mut w, s);
        let OutputMarks {
            columns,
            rows,
            frames,
        } = &self.marks;
        w.usize(columns.len());
        columns.iter().for_each(|c| w.str(c));
        w.usize(rows.len());
        rows.iter().for_each(|row| w.f64s(row));
        w.usize(frames.len());
        for (time, file) in frames {
            w.f64(*time);
            w.str(file);
        }
        w.bytes
    }

    /// Reads what [`Self::encode`] wrote; every byte must be used.
    pub fn decode(bytes: &[u8]) -> Read<Self> {
        let mut r = Reader::new(bytes);
        let u = r.vectors("displacements")?;
        let v_half = r.vectors("half-step velocities")?;
        let v_full = r.vectors("full-step velocities")?;
        let du_prev = r.vectors("last increments")?;
        let reaction = r.vectors("reactions")?;
        let step = r.usize("step")?;
        let time = r.f64("time")?;
        let time_step = r.f64("time step")?;
        let step_origin = r.usize("step origin")?;
        let time_origin = r.f64("time origin")?;
        let dt_before_resume = r.opt_f64("earlier time step")?;
        let energies = read_energies(&mut r)?;
        let pending = read_energies(&mut r)?;
        let history = read_history(&mut r)?;
        let mut n = || r.usize("contact totals");
        let contact_totals = ContactTotals {
            steps_with_contact: n()?,
            solves: n()?,
            not_converged: n()?,
            unresolved: n()?,
            iterations: n()?,
        };
        let schedule = read_schedule(&mut r)?;
        let columns = (0..r.usize("column count")?)
            .map(|_| r.str("column"))
            .collect::<Read<Vec<_>>>()?;
        let rows = (0..r.usize("row count")?)
            .map(|_| r.f64s("history row"))
            .collect::<Read<Vec<_>>>()?;
        let frames = (0..r.usize("frame count")?)
            .map(|_| Ok((r.f64("frame time")?, r.str("frame file")?)))
            .collect::<Read<Vec<_>>>()?;
        if r.remaining() != 0 {
            return Err(Short(format!(
                "{} bytes after the payload's end",
                r.remaining()
            )));
        }
        Ok(Self {
            state: RestartState {
                u,
                v_half,
                v_full,
                du_prev,
                reaction,
                step,
                time,
                time_step,
                step_origin,
                time_origin,
                dt_before_resume,
                energies,
                pending,
                history,
                contact_totals,
                schedule,
            },
            marks: OutputMarks {
                columns,
                rows,
                frames,
            },
        })
    }
}
