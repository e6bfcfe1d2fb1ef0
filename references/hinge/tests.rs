use super::*;
use impact_solver::material::microplane::experiments::{
    crack_opening_curve, FracturePath, QUASI_STATIC_RATE,
};
use impact_solver::material::microplane::MicroplaneConcrete;

/// The thesis beam (chapter 10): 600 x 300 mm, span 2.8 m; concrete E 30 GPa, f_t 2.7 MPa,
/// G_F 100 N/m (cases/materials/thesis-concrete.yaml and its calibration targets).
const H: f64 = 0.6;
const B: f64 = 0.3;
const L: f64 = 2.8;
const E: f64 = 30e9;
const FT: f64 = 2.7e6;
const GF: f64 = 100.0;

fn thesis_hinge(law: SofteningLaw) -> Hinge {
    Hinge::new(H, B, L, E, law)
}

fn linear() -> SofteningLaw {
    SofteningLaw::Linear {
        ft: FT,
        wc: 2.0 * GF / FT,
    }
}

#[test]
fn hinge_laws_start_at_ft_and_hold_their_fracture_energy() {
    let laws = [
        linear(),
        SofteningLaw::Mc2010 { ft: FT, gf: GF },
        SofteningLaw::Hordijk { ft: FT, gf: GF },
    ];
    for law in &laws {
        assert!((law.tensile_strength() - FT).abs() < 1e-9 * FT, "{law:?}");
        assert_eq!(law.stress(1.01 * law.critical_opening()), 0.0, "{law:?}");
        // Hordijk's constants give an area of 1.0007 G_F with w_c = 5.14 G_F / f_t.
        let gf = law.fracture_energy();
        assert!((gf - GF).abs() < 2e-3 * GF, "{law:?}: G_F {gf}");
    }
    let table = SofteningLaw::Tabulated {
        w: vec![0.0, 1e-5, 3e-5],
        sigma: vec![2e6, 1e6, 0.0],
    };
    assert!((table.stress(0.5e-5) - 1.5e6).abs() < 1e-6);
    assert!((table.stress(2e-5) - 0.5e6).abs() < 1e-6);
    assert_eq!(table.stress(4e-5), 0.0);
    assert!((table.fracture_energy() - (15.0 + 10.0)).abs() < 1e-9);
}

#[test]
fn hinge_elastic_limit() {
    let hinge = thesis_hinge(linear());
    let ei = E * hinge.inertia();
    let phi_cr = hinge.cracking_rotation();
    // Before cracking M = E I phi / s (the midpoint sum of a quadratic integrand is off by
    // (1 / layers)^2 = 6e-6).
    for f in [0.1, 0.5, 0.99] {
        let p = hinge.state(f * phi_cr);
        let exact = ei * f * phi_cr / hinge.length;
        assert!(
            (p.moment - exact).abs() < 1e-5 * exact,
            "{p:?} against {exact}"
        );
        assert!((p.bottom_strain - 0.5 * f * phi_cr / hinge.length * H).abs() < 1e-12);
        assert_eq!(p.crack_tip, 0.0);
        // No crack: the deflection is the elastic beam's.
        let elastic = p.load * L.powi(3) / (48.0 * ei);
        assert!((p.deflection - elastic).abs() < 1e-4 * elastic);
    }
    // First cracking at the elastic cracking moment f_t b h^2 / 6.
    let p = hinge.state(phi_cr);
    let m_cr = FT * B * H * H / 6.0;
    assert!(
        (p.moment - m_cr).abs() < 1e-5 * m_cr,
        "{} against {m_cr}",
        p.moment
    );
    let p = hinge.state(1.05 * phi_cr);
    assert!(p.crack_tip > 0.0 && p.moment > m_cr);
}

/// Closed form of the hinge with linear softening, derived independently of the layers. A
/// layer's stress against its strain `u` is trilinear: `E u` up to `e_t = f_t / E`, then
/// `f_t (e_c - u) / (e_c - e_t)` down to zero at `e_c = w_c / s`, zero beyond. With the strain
/// `u = eps_b - k y` (`k = phi / s`) the force and moment are integrals over `u`:
/// `N = (b / k) int sigma du`, `M = (b / k^2) int sigma u du` over `[eps_b - k h, eps_b]`
/// (`M` about any height once `N = 0`). Phases (Olesen's numbering): 0 elastic, `eps_b = k h / 2`;
/// I the crack carries stress everywhere (`e_t < eps_b <= e_c`), `N = 0` is the quadratic
/// `(E + r) x^2 - 2 (E k h + r e_c) x - (E e_t^2 - E k^2 h^2 - 2 r e_c e_t + r e_t^2) = 0` with
/// `r = f_t / (e_c - e_t)`, its smaller root; III a stress-free zone at the mouth
/// (`eps_b > e_c`), where `N = 0` gives the top strain `-sqrt(e_t e_c)`.
fn closed_form_linear_moment(phi: f64, s: f64, ft: f64, wc: f64) -> f64 {
    let k = phi / s;
    let (et, ec) = (ft / E, wc / s);
    let r = ft / (ec - et);
    let kh = k * H;
    let x = if kh <= 2.0 * et {
        0.5 * kh
    } else {
        let a = E + r;
        let b = -2.0 * (E * kh + r * ec);
        let c = -(E * et * et - E * kh * kh - 2.0 * r * ec * et + r * et * et);
        let root = 2.0 * c / (-b + (b * b - 4.0 * a * c).sqrt());
        if root <= ec {
            root
        } else {
            kh - (et * ec).sqrt()
        }
    };
    let top = x - kh;
    if x <= et {
        return E * B * H.powi(3) / 12.0 * k;
    }
    let m = x.min(ec);
    let elastic = E * (et.powi(3) - top.powi(3)) / 3.0;
    let softening = r * (ec * (m * m - et * et) / 2.0 - (m.powi(3) - et.powi(3)) / 3.0);
    B / (k * k) * (elastic + softening)
}

#[test]
fn hinge_matches_the_closed_form_of_linear_softening() {
    let wc = 2.0 * GF / FT;
    // 1000 layers: the midpoint sums are off by about (1 / layers)^2 of the moment, more as the
    // compression zone thins late in phase III.
    let mut hinge = thesis_hinge(linear());
    hinge.layers = 1000;
    let phi_cr = hinge.cracking_rotation();
    let m_peak = hinge.curve(1e3).peak.moment;
    let mut phases = [0; 3];
    for i in 1..200 {
        let phi = phi_cr * 0.05 * 1.04f64.powi(i);
        let p = hinge.state(phi);
        let exact = closed_form_linear_moment(phi, hinge.length, FT, wc);
        if phi > 2.0 * phi_cr && exact < 0.05 * m_peak {
            break;
        }
        let phase = if p.bottom_strain <= FT / E {
            0
        } else if p.bottom_strain <= wc / hinge.length {
            1
        } else {
            2
        };
        phases[phase] += 1;
        assert!(
            (p.moment - exact).abs() < 1e-4 * exact,
            "phi {phi:e}: layers {} against closed form {exact}",
            p.moment
        );
    }
    assert!(
        phases.iter().all(|&n| n >= 5),
        "points per phase {phases:?}"
    );
}

#[test]
fn hinge_ductile_and_brittle_limits() {
    let plastic = FT * B * H * H / 2.0;
    let elastic = FT * B * H * H / 6.0;
    // No softening to speak of (w_c = 1 km): the moment tends to the rigid-plastic
    // f_t b h^2 / 2 as the compression zone shrinks (its depth is about h sqrt(phi_cr / phi),
    // 1 % of h at 1e4 phi_cr, where M / M_p = 1 - 2 c / (3 h) = 0.993).
    let mut ductile = thesis_hinge(SofteningLaw::Linear { ft: FT, wc: 1e3 });
    ductile.layers = 1000;
    let near = ductile.curve(1e2).peak.moment / plastic;
    let far = ductile.curve(1e4).peak.moment / plastic;
    assert!(near < far && far < 1.0 && far > 0.985, "{near} then {far}");
    // Sudden loss of strength (w_c 1e-3 of the elastic opening s f_t / E): the peak is the
    // cracking moment f_t b h^2 / 6.
    let s = 0.5 * H;
    let brittle = thesis_hinge(SofteningLaw::Linear {
        ft: FT,
        wc: 1e-3 * s * FT / E,
    });
    let ratio = brittle.curve(1e2).peak.moment / elastic;
    assert!((ratio - 1.0).abs() < 2e-3, "{ratio}");
}

#[test]
fn hinge_peak_falls_with_the_law_shape_at_equal_fracture_energy() {
    let peak = |law| thesis_hinge(law).peak(1e3).load;
    let lin = peak(linear());
    let mc = peak(SofteningLaw::Mc2010 { ft: FT, gf: GF });
    let hor = peak(SofteningLaw::Hordijk { ft: FT, gf: GF });
    let cracking = 4.0 * FT * B * H * H / 6.0 / L;
    assert!(
        lin > mc && mc > hor && hor > cracking,
        "{lin} {mc} {hor} {cracking}"
    );
}

#[test]
fn hinge_solve_is_fast() {
    // The reference's solve: the peak of the slowest law (Hordijk's exponential).
    let hinge = thesis_hinge(SofteningLaw::Hordijk { ft: FT, gf: GF });
    let start = std::time::Instant::now();
    let peak = hinge.peak(1e4);
    let elapsed = start.elapsed().as_secs_f64();
    assert!(elapsed < 1.0, "{elapsed} s");
    let curve = hinge.curve(1e4);
    assert!((curve.peak.moment - peak.moment).abs() < 1e-9 * peak.moment);
    // Rotation rises along the curve; the deflection after the peak may turn back (snap-back).
    assert!(curve
        .points
        .windows(2)
        .all(|p| p[1].rotation > p[0].rotation));
}

#[test]
#[ignore = "prints the thesis beam's peak loads; run with --ignored --nocapture"]
fn hinge_thesis_beam_peaks() {
    // The microplane model's own law at the 50 mm cells of the thesis beam's mesh.
    let model = thesis_concrete();
    let (w, sigma) = crack_opening_curve(&model, 0.05);
    let own = SofteningLaw::Tabulated { w, sigma };
    let (_, tension) = FracturePath::of_driver(model.parameters.tension_driver)
        .tension(&model, 0.05, QUASI_STATIC_RATE)
        .expect("tension");
    println!(
        "own law at 50 mm: f_t {:.4} MPa, int sigma dw {:.2} N/m, crack-band h int sigma d eps \
         {:.2} N/m, w_end {:.3} mm",
        own.tensile_strength() / 1e6,
        own.fracture_energy(),
        tension.fracture_energy,
        own.critical_opening() * 1e3
    );
    for (name, law) in [
        ("linear", linear()),
        ("MC2010", SofteningLaw::Mc2010 { ft: FT, gf: GF }),
        ("Hordijk", SofteningLaw::Hordijk { ft: FT, gf: GF }),
        ("own", own),
    ] {
        let start = std::time::Instant::now();
        let curve = thesis_hinge(law).curve(1e4);
        let p = curve.peak;
        println!(
            "{name:8} peak P {:8.2} kN  M {:7.2} kN m  sigma_N/f_t {:.3}  at phi {:.3e} rad, \
             deflection {:.3} mm, crack tip {:.0} mm ({} points, {:.3} s)",
            p.load / 1e3,
            p.moment / 1e3,
            1.5 * p.load * L / (B * H * H) / FT,
            p.rotation,
            p.deflection * 1e3,
            p.crack_tip * 1e3,
            curve.points.len(),
            start.elapsed().as_secs_f64()
        );
    }
}

fn thesis_concrete() -> MicroplaneConcrete {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cases/materials/thesis-concrete.yaml");
    let parameters = impact_solver::material::read_microplane_file(&path).expect("parameter file");
    MicroplaneConcrete::new(parameters).expect("valid parameters")
}

#[test]
fn hinge_own_law_holds_the_crack_band_fracture_energy() {
    let model = thesis_concrete();
    let h = 0.05;
    let (w, sigma) = crack_opening_curve(&model, h);
    assert!(w.windows(2).all(|w| w[1] > w[0]) && w[0] == 0.0);
    // The test the calibration defines GF on for the concrete's tension driver.
    let path = FracturePath::of_driver(model.parameters.tension_driver);
    let (_, tension) = path.tension(&model, h, QUASI_STATIC_RATE).expect("tension");
    assert_eq!(sigma[0], tension.peak_stress);
    let law = SofteningLaw::Tabulated { w, sigma };
    let gf = law.fracture_energy();
    assert!(
        (gf - tension.fracture_energy).abs() < 0.02 * tension.fracture_energy,
        "int sigma dw {gf} against h int sigma d eps {}",
        tension.fracture_energy
    );
}

/// A pre-peak branch that is the linear one, `(0, 0)` to `(f_t / E, f_t)`, is Olesen's hinge:
/// the same moments at every rotation.
#[test]
fn linear_pre_peak_branch_is_olesens_hinge() {
    let plain = thesis_hinge(SofteningLaw::Hordijk { ft: FT, gf: GF });
    let branch = PrePeak {
        strain: vec![0.0, 0.5 * FT / E, FT / E],
        stress: vec![0.0, 0.5 * FT, FT],
    };
    let with = plain.clone().with_pre_peak(branch);
    assert_eq!(with.cracking_rotation(), plain.cracking_rotation());
    assert_same_moments(&plain, &with, &[0.5, 1.0, 2.0, 5.0, 20.0], 1e-9);
}

/// `b`'s moments equal `a`'s within `tolerance` (relative) at rotations of `ratios` times `a`'s
/// cracking rotation.
fn assert_same_moments(a: &Hinge, b: &Hinge, ratios: &[f64], tolerance: f64) {
    for f in ratios {
        let phi = f * a.cracking_rotation();
        let (ma, mb) = (a.state(phi).moment, b.state(phi).moment);
        assert!(
            (ma - mb).abs() < tolerance * ma,
            "phi / phi_cr = {f}: {ma} against {mb}"
        );
    }
}

/// A rising branch that bends over (secant 0.7 E at the peak) puts more stress into the layers
/// below the crack tip at the same strains, so the peak moment is higher than Olesen's, and
/// below the rigid-plastic moment `f_t b h^2 / 2`; past the peak the crack law is shifted by the
/// bulk's inelastic strain, so the layer law is continuous at `eps_p`.
#[test]
fn a_rounded_pre_peak_branch_raises_the_peak() {
    let law = SofteningLaw::Hordijk { ft: FT, gf: GF };
    let plain = thesis_hinge(law.clone());
    let eps_p = FT / (0.7 * E);
    // sigma = E eps (1 - c eps) reaching f_t at eps_p: c = (1 - f_t / (E eps_p)) / eps_p.
    let c = (1.0 - 0.7) / eps_p;
    let strain: Vec<f64> = (0..=50).map(|i| eps_p * i as f64 / 50.0).collect();
    let mut stress: Vec<f64> = strain.iter().map(|e| E * e * (1.0 - c * e)).collect();
    *stress.last_mut().unwrap() = FT;
    let rounded = plain.clone().with_pre_peak(PrePeak { strain, stress });
    let below = rounded.layer_stress(eps_p * (1.0 - 1e-9));
    let above = rounded.layer_stress(eps_p * (1.0 + 1e-9));
    assert!((below - FT).abs() < 1e-5 * FT && (above - FT).abs() < 1e-5 * FT);
    let (a, b) = (plain.peak(1e4).moment, rounded.peak(1e4).moment);
    assert!(b > a && b < FT * B * H * H / 2.0, "{a} against {b}");
}

/// A notch of depth a_0 leaves the hinge of the ligament: the moments of a notched beam of depth
/// h are those of an unnotched beam of depth h - a_0 at the same rotation (the normal force
/// vanishes, so the moment does not depend on the axis).
#[test]
fn a_notched_hinge_is_the_hinge_of_its_ligament() {
    let law = SofteningLaw::Hordijk { ft: FT, gf: GF };
    let a0 = 0.25 * H;
    let notched = Hinge::new(H, B, L, E, law.clone()).with_notch(a0);
    let ligament = Hinge::new(H - a0, B, L, E, law);
    assert_eq!(notched.length, ligament.length);
    assert_same_moments(&ligament, &notched, &[0.5, 1.0, 3.0, 10.0], 1e-7);
}

#[test]
#[ignore = "prints the thesis beam's hinge curve with the rising branch; run with --ignored --nocapture"]
fn hinge_thesis_beam_curve_with_rising_branch() {
    // After the peak the load falls by 12.7 kN over 8.5 um of deflection: nearly vertical, so a
    // beam only slightly more compliant than the hinge's (shear, supports, the plate) snaps
    // back under load-point displacement control.
    let model = thesis_concrete();
    let (law, pre) = own_law_with_pre_peak(&model, 0.05);
    let hinge = thesis_hinge(law).with_pre_peak(pre);
    let curve = hinge.curve(1e4);
    for p in curve.points.iter().step_by(2).take(60) {
        println!(
            "phi {:.3e} M {:.2} kNm P {:.1} kN delta {:.4} mm tip {:.0} mm",
            p.rotation,
            p.moment / 1e3,
            p.load / 1e3,
            p.deflection * 1e3,
            p.crack_tip * 1e3
        );
    }
}

/// Both branches of the thesis concrete's own law join at the peak: the rising branch starts at
/// the origin, rises monotonically to the crack-opening law's `f_t` at its last point, and the
/// crack-opening law counted from the peak is the crack band's reading less exactly its plateau
/// at `f_t` over the pre-peak opening `h (eps_p - f_t / E)`, which the hinge's bulk now holds.
#[test]
fn own_law_branches_join_at_the_peak() {
    let model = thesis_concrete();
    let (law, pre) = own_law_with_pre_peak(&model, 0.05);
    assert_eq!((pre.strain[0], pre.stress[0]), (0.0, 0.0));
    assert!(pre.strain.windows(2).all(|w| w[1] > w[0]));
    assert!(pre.stress.windows(2).all(|s| s[1] >= s[0]));
    assert_eq!(*pre.stress.last().unwrap(), law.tensile_strength());
    let (w, sigma) = crack_opening_curve(&model, 0.05);
    let lumped = SofteningLaw::Tabulated { w, sigma }.fracture_energy();
    let counted = law.fracture_energy();
    let ft = law.tensile_strength();
    let plateau = ft * 0.05 * (pre.peak_strain() - ft / model.parameters.youngs_modulus);
    assert!(
        (lumped - plateau - counted).abs() < 1e-9 * lumped,
        "{counted} + {plateau} against {lumped} N/m"
    );
}

/// The opening front of a linear-softening hinge in closed form: with `sigma = f_t (1 - w /
/// w_c)` a cracked layer at strain `eps` opens `w = s (eps - f_t / E) / (1 - s f_t / (E w_c))`,
/// and `eps(y) = eps_b - k y`, so the opening `w_f` is reached at
/// `y = (eps_b - f_t / E - w_f (1 - s f_t / (E w_c)) / s) / k`.
#[test]
fn opening_front_of_linear_softening_in_closed_form() {
    let hinge = thesis_hinge(linear());
    let (SofteningLaw::Linear { ft, wc }, e, s) = (&hinge.law, hinge.youngs_modulus, hinge.length)
    else {
        panic!("a linear law")
    };
    let (ft, wc) = (*ft, *wc);
    let curve = hinge.curve(400.0);
    let mut checked = 0;
    for p in curve
        .points
        .iter()
        .filter(|p| p.crack_tip > 0.05 && p.crack_tip < 0.55)
    {
        let k = p.rotation / s;
        for w_f in [0.2 * wc, 0.5 * wc] {
            let eps_f = ft / e + w_f * (1.0 - s * ft / (e * wc)) / s;
            let exact = (p.bottom_strain - eps_f) / k;
            if !(0.0..hinge.depth).contains(&exact) || p.bottom_strain - eps_f <= 0.0 {
                continue;
            }
            let front = hinge.opening_front(p, w_f);
            assert!((front - exact).abs() < 1e-9, "{front} against {exact}");
            // The front lies below the tip of the cohesive zone (w = 0).
            assert!(front < p.crack_tip);
            checked += 1;
        }
    }
    assert!(checked > 10, "{checked}");
    // Before any crack, no front.
    assert_eq!(hinge.opening_front(&curve.points[1], 1e-6), 0.0);
}
