//! The trials the fill and swap evaluations run on (one list, so both speak of the same
//! labs), a corpus trial's markers read as a repair `Trial` in mm, and a trial's activity.

use repair::Trial;

/// Each corpus's folder on this machine, by the short name the file lists use ("samples",
/// "extra", "fullbody", "more", "labs"); None for a corpus not found.
pub fn roots() -> std::collections::BTreeMap<&'static str, Option<std::path::PathBuf>> {
    [
        ("samples", testkit::c3d_samples()),
        ("extra", testkit::c3d_extra()),
        ("fullbody", testkit::c3d_fullbody()),
        ("more", testkit::c3d_more()),
        ("labs", testkit::c3d_labs()),
    ]
    .into_iter()
    .collect()
}

/// The file's markers (points that are not model outputs) as a trial in mm.
///
/// A sample at exactly (0, 0, 0) counts as missing here, whatever its residual says: no
/// marker sits on the lab's origin to the last bit, and the writers that store such samples
/// mean a lost one (ART-Human sets every point of a frame where the body was lost there;
/// Vicon's files hold them in virtual markers it could not compute). As the truth of an
/// artificial gap such a sample would score a fill against the origin: 206 of the 353 gaps
/// of `arthuman-sample.c3d` touched its one such frame, the only stretches there not
/// skipped as computed points (the frame breaks their constant distances).
#[allow(dead_code)]
pub fn load(path: &std::path::Path) -> Result<Trial, String> {
    load_with(path, false)
}

/// [`load`], with samples of residual 0 (the C3D manual's mark for processed points: the
/// capture software's fills) counted as missing when the file has any residual above 0.
pub fn load_recorded(path: &std::path::Path) -> Result<Trial, String> {
    load_with(path, true)
}

fn load_with(path: &std::path::Path, recorded: bool) -> Result<Trial, String> {
    let c = c3d::read_file(path).map_err(|e| e.to_string())?;
    trial_of(&c, &markers_of(&c), recorded)
}

/// The points of `c` an evaluation takes as markers, in file order: neither model outputs
/// nor unlabelled trajectories (`*51`, `Unlabeled 3`, an empty label: see
/// `repair::Unlabelled`). A repair fills and swaps labelled markers only, so the
/// evaluations judge the same points; the unlabelled ones are the reclaim evaluation's.
pub fn markers_of(c: &c3d::C3d) -> Vec<usize> {
    let outputs = c.model_output_labels();
    let unlabelled = repair::Unlabelled::common();
    let labels = c.point_labels();
    (0..labels.len())
        .filter(|&i| !outputs.contains(&labels[i]) && !unlabelled.is_unlabelled(&labels[i]))
        .collect()
}

/// Whether a corpus's trials may hold the capture software's fills (residual 0), which are
/// no truth: there, where a trial has recorded residuals, residual 0 counts as missing
/// ([`load_recorded`]). `c3d-more`'s and `c3d-labs`' trials were published after their
/// labs' processing; the older corpora's files are the formats' samples as written.
pub fn holds_fills(corpus: &str) -> bool {
    matches!(corpus, "more" | "labs")
}

/// The trial of `c`'s points `points` (in that order), in mm: a sample is missing where the
/// file marks it so, at the origin (see [`load`]), or, with `recorded`, of residual 0 when
/// the file has any residual above 0 among those points. A point with no sample left is not
/// in the trial. One reading for every evaluation, so that one that keeps other points
/// (`fill_eval --donors`, the records' own point lists) reads each sample as the rest do.
pub fn trial_of(c: &c3d::C3d, points: &[usize], recorded: bool) -> Result<Trial, String> {
    let k = c3d::mm_per_unit(&c.point_units());
    let p = c.points();
    let drop_processed = recorded
        && points.iter().any(|&i| {
            let r = p.residuals(i);
            (0..p.frames()).any(|f| p.is_valid(f, i) && r[f] > 0.0)
        });
    let (mut xyz, mut valid) = (Vec::new(), Vec::new());
    for &i in points {
        let r = p.residuals(i);
        let t = p.trajectory(i);
        let v: Vec<bool> = (0..p.frames())
            .map(|f| p.is_valid(f, i) && !(drop_processed && r[f] == 0.0) && t[f] != [0.0; 3])
            .collect();
        if !v.iter().any(|&x| x) {
            continue;
        }
        xyz.push(
            t.iter()
                .map(|q| [q[0] as f64 * k, q[1] as f64 * k, q[2] as f64 * k])
                .collect(),
        );
        valid.push(v);
    }
    Trial::new(c.point_rate() as f64, xyz, valid).map_err(|e| e.to_string())
}

/// The trials the evaluations run on (`fill_eval`, `swap_eval`), one list so both speak
/// of the same labs: (set, lab, corpus, path). Copies of one trial in other formats are listed once; files
/// too short for gaps, without markers, with every sample flagged invalid or static (NexGen
/// test1.c3d holds one pose) are left out.
pub const FILES: &[(&str, &str, &str, &str)] = &[
    (
        "walking",
        "mac",
        "samples",
        "sample_00/Motion Analysis Corporation/Walk1.c3d",
    ),
    (
        "walking",
        "ist",
        "samples",
        "sample_00/Innovative Sports Training/Gait with EMG.c3d",
    ),
    (
        "walking",
        "coda",
        "samples",
        "sample_00/Codamotion/codamotion_gaitwands_20150204.c3d",
    ),
    (
        "walking",
        "coda",
        "samples",
        "sample_00/Codamotion/codamotion_gaitwands_19970212.c3d",
    ),
    ("walking", "amass", "samples", "sample_01/Eb015pr.c3d"),
    ("walking", "vicon370", "samples", "sample_02/pc_real.c3d"),
    ("walking", "vicon370", "samples", "sample_03/gait-raw.c3d"),
    ("walking", "vicon370", "samples", "sample_04/sub_labels.c3d"),
    ("walking", "mac", "samples", "sample_06/newwalk.c3d"),
    ("walking", "mac", "samples", "sample_06/MACsample.c3d"),
    ("walking", "viconws", "samples", "sample_09/PlugInC3D.c3d"),
    ("walking", "amti", "samples", "sample_10/TYPE-3.c3d"),
    ("walking", "mac", "samples", "sample_11/evart.c3d"),
    ("walking", "viconws", "samples", "sample_11/2198928.c3d"),
    (
        "walking",
        "nexus",
        "samples",
        "sample_25/analogfpscale03.c3d",
    ),
    (
        "walking",
        "nexus",
        "samples",
        "sample_25/analogfpscale04.c3d",
    ),
    ("walking", "bts", "samples", "sample_28/dynamic.C3D"),
    ("walking", "marche", "samples", "sample_30/marche281.c3d"),
    ("walking", "marche", "samples", "sample_30/admarche2.c3d"),
    ("walking", "mac", "extra", "btkdata_Gait.c3d"),
    ("walking", "bts", "extra", "btkdata_561xxa01_anonym.C3D"),
    ("fullbody", "cmu", "fullbody", "85_02.c3d"),
    ("fullbody", "cmu", "fullbody", "85_12.c3d"),
    ("fullbody", "cmu", "fullbody", "135_02.c3d"),
    ("fullbody", "numediart", "fullbody", "03_rolling.c3d"),
    (
        "fullbody",
        "mac",
        "samples",
        "sample_00/Motion Analysis Corporation/Sample_Jump2.c3d",
    ),
    (
        "fullbody",
        "art",
        "samples",
        "sample_00/Advanced Realtime Tracking GmbH/arthuman-sample.c3d",
    ),
    ("fullbody", "art", "samples", "sample_37/ART-Human_real.c3d"),
    ("fullbody", "phoenix", "samples", "sample_13/Dance1.c3d"),
    ("fullbody", "mm", "samples", "sample_34/AlbertoREAL.c3d"),
    ("fullbody", "mm", "samples", "sample_34/Basketball.c3d"),
    (
        "fullbody",
        "phasespace",
        "samples",
        "sample_20/phasespace_sample.c3d",
    ),
    ("fullbody", "optitrack", "extra", "btkdata_mocap36.c3d"),
    // `../c3d-more`: one lab per source, except the CMU trials (the lab of `cmu` above).
    // Its other labs chose nothing: they are the held-apart labs.
    (
        "walking",
        "cmu",
        "more",
        "EmbodiedCognition__pagoda__cooper-motion.c3d",
    ),
    (
        "walking",
        "HansUniVie",
        "more",
        "HansUniVie__MuscleLength__test.c3d",
    ),
    (
        "fullbody",
        "PhilD001",
        "more",
        "PhilD001__biomechZoo__hockey_wristshot009.c3d",
    ),
    (
        "fullbody",
        "PhilD001",
        "more",
        "PhilD001__biomechZoo__ti003.c3d",
    ),
    (
        "walking",
        "cadop",
        "more",
        "cadop__pyCGM__Movement_trial.c3d",
    ),
    (
        "fullbody",
        "keenon",
        "more",
        "keenon__nimblephysics__JA1Gait35.c3d",
    ),
    (
        "fullbody",
        "cmu",
        "more",
        "keenon__nimblephysics__cmu_02_05.c3d",
    ),
    (
        "fullbody",
        "cmu",
        "more",
        "keenon__nimblephysics__cmu_dribble_shoot_basketball.c3d",
    ),
    (
        "fullbody",
        "keenon",
        "more",
        "keenon__nimblephysics__nick_freeform_001.c3d",
    ),
    (
        "fullbody",
        "keenon",
        "more",
        "keenon__nimblephysics__squat.c3d",
    ),
    (
        "walking",
        "martinfelis",
        "more",
        "martinfelis__puppeteer__testdata.c3d",
    ),
    (
        "fullbody",
        "opensim",
        "more",
        "opensim-org__opensim-core__doubleLegLanding.c3d",
    ),
    (
        "walking",
        "opensim",
        "more",
        "opensim-org__opensim-core__walking2.c3d",
    ),
    (
        "walking",
        "pyomeca",
        "more",
        "pyomeca__ezc3d-testFiles__FP_Type1.c3d",
    ),
    (
        "walking",
        "pyomeca",
        "more",
        "pyomeca__ezc3d-testFiles__Qualisys.c3d",
    ),
    (
        "walking",
        "qualisys",
        "more",
        "qualisys__cgm2-web-report-uploader__ClinicalGait_Gait1.c3d",
    ),
    (
        "walking",
        "qualisys",
        "more",
        "qualisys__cgm2-web-report-uploader__FunctionalKnee_GaitFB2.c3d",
    ),
    (
        "walking",
        "tsalemink",
        "more",
        "tsalemink__C3D-parser__AUC_CB_Dynamic0003.c3d",
    ),
    (
        "walking",
        "tsalemink",
        "more",
        "tsalemink__C3D-parser__FMC_MH0222_BP15.c3d",
    ),
    (
        "walking",
        "tsalemink",
        "more",
        "tsalemink__C3D-parser__RBWH_bfnd_w1.c3d",
    ),
    // `../c3d-labs` (issue 45 item 7): one lab per source owner, none chosen on; they are
    // the held-apart labs of the activities beyond walking (drop jumps, running, cutting,
    // sit-to-stand, lifting). pyorerun's running stance is its own lab (Qualisys, another
    // repository than pyomeca's lifting trial and ezc3d's test files).
    (
        "walking",
        "RehabEngGroup",
        "labs",
        "RehabEngGroup__MOtoNMS__Walking1.c3d",
    ),
    (
        "walking",
        "RehabEngGroup",
        "labs",
        "RehabEngGroup__MOtoNMS__Walking3.c3d",
    ),
    (
        "walking",
        "RehabEngGroup",
        "labs",
        "RehabEngGroup__MOtoNMS__Fast_Walking.c3d",
    ),
    (
        "walking",
        "RehabEngGroup",
        "labs",
        "RehabEngGroup__MOtoNMS__Running_1.c3d",
    ),
    (
        "fullbody",
        "RehabEngGroup",
        "labs",
        "RehabEngGroup__MOtoNMS__Cross_-_Overs_2.c3d",
    ),
    (
        "walking",
        "psbiomech",
        "labs",
        "psbiomech__lasem-data-processing__FAILT01_Walk01.c3d",
    ),
    (
        "fullbody",
        "psbiomech",
        "labs",
        "psbiomech__lasem-data-processing__FAILT01_SLDJ01.c3d",
    ),
    (
        "fullbody",
        "psbiomech",
        "labs",
        "psbiomech__lasem-data-processing__FAILT01_SLDJ03.c3d",
    ),
    (
        "fullbody",
        "psbiomech",
        "labs",
        "psbiomech__lasem-data-processing__FAILT01_SLDJ05.c3d",
    ),
    (
        "fullbody",
        "psbiomech",
        "labs",
        "psbiomech__lasem-data-processing__FAILT01_SLDJ06.c3d",
    ),
    (
        "walking",
        "RealTimeBiomechanics",
        "labs",
        "RealTimeBiomechanics__rtosim__walking_1.c3d",
    ),
    (
        "walking",
        "BMClab",
        "labs",
        "BMClab__BMC__C_S05_T08_3_Cycle.c3d",
    ),
    ("walking", "BMClab", "labs", "BMClab__BMC__Gait.c3d"),
    (
        "walking",
        "s2mLab",
        "labs",
        "s2mLab__BioptimPaperExamples__normal01_out.c3d",
    ),
    (
        "walking",
        "regifukuchi",
        "labs",
        "regifukuchi__BMC-RIC-running-biomechanics__RBDS001runT35.c3d",
    ),
    (
        "walking",
        "regifukuchi",
        "labs",
        "regifukuchi__BMC-RIC-running-biomechanics__20140515T133244_run.c3d",
    ),
    (
        "walking",
        "basgoncalves",
        "labs",
        "basgoncalves__msk_modelling_python__sprint_1.c3d",
    ),
    (
        "walking",
        "pyorerun",
        "labs",
        "pyomeca__pyorerun__Running_0002.c3d",
    ),
    (
        "fullbody",
        "vaila",
        "labs",
        "vaila-multimodaltoolbox__vaila__C3D_to_CSV_01.c3d",
    ),
    (
        "fullbody",
        "pyomeca",
        "labs",
        "pyomeca__pyomeca__markers_analogs.c3d",
    ),
    (
        "fullbody",
        "mjhmilla",
        "labs",
        "mjhmilla__MillardSreenivasaMombaur2017__stoop1_t169_f620f800.c3d",
    ),
];

/// Words of a trial's description, in the order they are tried, and the activity each
/// names: sports first, as "ice-hockey shot, Plug-in Gait + stick" names a marker set
/// after the gait it was made for.
const ACTIVITY_WORDS: &[(&str, &str)] = &[
    ("hockey", "sports"),
    ("basketball", "sports"),
    ("punch", "sports"),
    ("golf", "sports"),
    ("tennis", "sports"),
    ("running", "running"),
    ("sprint", "running"),
    ("cutting", "cutting"),
    ("sit-to-stand", "sit-to-stand"),
    ("lifting", "lifting"),
    ("landing", "landing"),
    ("jump", "jumping"),
    ("squat", "squats"),
    ("stair", "stairs"),
    ("dance", "dance"),
    ("rolling", "rolling on the floor"),
    ("free", "free movement"),
    ("walk", "walking"),
    ("gait", "walking"),
];

/// The activity of trial `rel` of a corpus, by rule, not by a list of files: the words of
/// its row in the corpus's README (`readme`: the activity column where the table has one,
/// else the whole row), else of its file name; a trial neither names is what the corpus
/// list's `set` says (`walking`) or `other full body`.
pub fn activity(readme: Option<&str>, rel: &str, set: &str) -> &'static str {
    let name = rel.rsplit('/').next().unwrap_or(rel);
    let stem = name.rsplit_once('.').map_or(name, |s| s.0);
    let cells = |l: &str| -> Vec<String> {
        l.trim()
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_lowercase())
            .collect()
    };
    let described = readme.and_then(|text| {
        let mut column = None;
        for l in text.lines().filter(|l| l.trim_start().starts_with('|')) {
            let c = cells(l);
            if column.is_none() && c.iter().any(|c| c == "file") {
                column = c.iter().position(|c| c == "activity");
                continue;
            }
            let names_it = c.first().is_some_and(|first| {
                first.split([',', '/']).map(str::trim).any(|n| {
                    n == rel.to_lowercase() || n == name.to_lowercase() || n == stem.to_lowercase()
                })
            });
            if names_it {
                return Some(
                    column
                        .and_then(|k| c.get(k).cloned())
                        .unwrap_or_else(|| c.join(" ")),
                );
            }
        }
        None
    });
    let find = |text: &str| {
        let text = text.to_lowercase();
        ACTIVITY_WORDS
            .iter()
            .find(|(w, _)| text.contains(w))
            .map(|a| a.1)
    };
    described
        .as_deref()
        .and_then(find)
        .or_else(|| find(stem))
        .unwrap_or(if set == "walking" {
            "walking"
        } else {
            "other full body"
        })
}
