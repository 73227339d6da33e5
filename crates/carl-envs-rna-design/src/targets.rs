//! Target structures of the RNA design benchmarks: Eterna100 (V1, LEARNA's and CARL's `eterna`,
//! and V2) and Rfam-Taneda ship inside the binary (data/rna/, licences and provenance there);
//! Rfam-Learn is read from the data directory (`$CARL_SPEC_DATA/rna/rfam_learn_{split}/N.rna`,
//! LEARNA's layout).

use std::path::{Path, PathBuf};

/// Environment variable naming the data directory (Rfam-Learn lives in `rna/` below it).
pub const DATA_ENV_VAR: &str = "CARL_SPEC_DATA";

const ETERNA100_TSV: &str = include_str!("../data/rna/eterna100_puzzles.tsv");

/// Rfam-Taneda `1.rna … 29.rna` (file number = id), as LEARNA reads them (`read_text().rstrip()`).
const RFAM_TANEDA: [&str; 29] = {
    macro_rules! taneda {
        ($($n:literal),*) => { [$(include_str!(concat!("../data/rna/rfam_taneda/", $n, ".rna"))),*] };
    }
    taneda!(
        "1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12", "13", "14", "15", "16", "17", "18", "19", "20",
        "21", "22", "23", "24", "25", "26", "27", "28", "29"
    )
};

/// A benchmark the targets come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dataset {
    /// Eterna100 V1 (12–400 nt), LEARNA's and CARL's `eterna`; ids are puzzle numbers 1–100.
    Eterna,
    /// Eterna100 V2 (the 2024 revision: 19 puzzles redesigned), ids 1–100.
    EternaV2,
    /// The 29 Rfam-Taneda targets (54–451 nt), ids 1–29.
    RfamTaneda,
    /// Rfam-Learn (LEARNA's train 65,000 / validation 100 / test 100), read from the data directory.
    RfamLearn(RfamLearnSplit),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RfamLearnSplit {
    Train,
    Validation,
    Test,
}

impl RfamLearnSplit {
    pub fn name(self) -> &'static str {
        match self {
            RfamLearnSplit::Train => "train",
            RfamLearnSplit::Validation => "validation",
            RfamLearnSplit::Test => "test",
        }
    }
}

impl Dataset {
    /// The spec's choice names (`dataset` feature), plus `rfam_learn_{train,validation,test}`.
    pub fn from_name(name: &str) -> Option<Dataset> {
        Some(match name {
            "eterna" => Dataset::Eterna,
            "eterna_v2" => Dataset::EternaV2,
            "rfam_taneda" => Dataset::RfamTaneda,
            "rfam_learn" | "rfam_learn_train" => Dataset::RfamLearn(RfamLearnSplit::Train),
            "rfam_learn_validation" => Dataset::RfamLearn(RfamLearnSplit::Validation),
            "rfam_learn_test" => Dataset::RfamLearn(RfamLearnSplit::Test),
            _ => return None,
        })
    }

    pub fn name(self) -> String {
        match self {
            Dataset::Eterna => "eterna".into(),
            Dataset::EternaV2 => "eterna_v2".into(),
            Dataset::RfamTaneda => "rfam_taneda".into(),
            Dataset::RfamLearn(split) => format!("rfam_learn_{}", split.name()),
        }
    }
}

/// One design target.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Target {
    /// Id within its dataset (puzzle number / file number).
    pub id: u32,
    pub structure: String,
    /// 0-based partner of every site.
    pub partner: Vec<Option<usize>>,
}

impl Target {
    fn new(id: u32, structure: &str, origin: &str) -> Result<Target, TargetError> {
        let structure = structure.trim_end().to_string();
        let partner = pair_table(&structure).map_err(|reason| TargetError::BadStructure {
            origin: origin.to_string(),
            reason,
        })?;
        if structure.is_empty() {
            return Err(TargetError::BadStructure {
                origin: origin.to_string(),
                reason: "empty structure".into(),
            });
        }
        if structure.len() > carl_rna::MAX_LEN {
            return Err(TargetError::BadStructure {
                origin: origin.to_string(),
                reason: format!(
                    "{} nt is longer than the folding limit of {} nt",
                    structure.len(),
                    carl_rna::MAX_LEN
                ),
            });
        }
        Ok(Target { id, structure, partner })
    }

    pub fn len(&self) -> usize {
        self.structure.len()
    }

    pub fn is_empty(&self) -> bool {
        self.structure.is_empty()
    }
}

fn pair_table(structure: &str) -> Result<Vec<Option<usize>>, String> {
    let mut partner = vec![None; structure.len()];
    let mut open = Vec::new();
    for (k, ch) in structure.bytes().enumerate() {
        match ch {
            b'.' => {}
            b'(' => open.push(k),
            b')' => {
                let i = open.pop().ok_or_else(|| format!("position {}: unmatched ')'", k + 1))?;
                partner[i] = Some(k);
                partner[k] = Some(i);
            }
            other => {
                return Err(format!(
                    "position {}: {:?} is not '.', '(' or ')'",
                    k + 1,
                    other as char
                ));
            }
        }
    }
    match open.last() {
        Some(i) => Err(format!("position {}: unmatched '('", i + 1)),
        None => Ok(partner),
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TargetError {
    #[error("{dataset}: no target with id {id} (ids are {valid})")]
    UnknownId { dataset: String, id: u32, valid: String },
    #[error(
        "Rfam-Learn not found: {path} does not exist. Rfam-Learn cannot be shipped with carl-spec; \
         get it with LEARNA (https://github.com/automl/learna: `make data`, or its \
         src/data/download_and_build_rfam_learn.sh), then copy its data/rfam_learn/{{train,validation,test}} \
         folders to DIR/rna/rfam_learn_{{train,validation,test}} and set {DATA_ENV_VAR}=DIR"
    )]
    RfamLearnMissing { path: PathBuf },
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
    #[error("{origin}: {reason}")]
    BadStructure { origin: String, reason: String },
    #[error("{dataset}: no targets selected")]
    NoTargets { dataset: String },
}

/// The targets of `dataset` with the given ids (all of them when `ids` is `None`), in id order
/// (ids in the order given). `data_dir` overrides `$CARL_SPEC_DATA` (only Rfam-Learn needs it).
pub fn load(dataset: Dataset, ids: Option<&[u32]>, data_dir: Option<&Path>) -> Result<Vec<Target>, TargetError> {
    let all: Vec<Target> = match dataset {
        Dataset::Eterna | Dataset::EternaV2 => eterna100(dataset == Dataset::EternaV2)?,
        Dataset::RfamTaneda => RFAM_TANEDA
            .iter()
            .zip(1..)
            .map(|(s, id)| Target::new(id, s, &format!("rfam_taneda/{id}.rna")))
            .collect::<Result<_, _>>()?,
        Dataset::RfamLearn(split) => return rfam_learn(split, ids, data_dir),
    };
    select(dataset, all, ids)
}

fn select(dataset: Dataset, all: Vec<Target>, ids: Option<&[u32]>) -> Result<Vec<Target>, TargetError> {
    let chosen = match ids {
        None => all,
        Some(ids) => ids
            .iter()
            .map(|&id| {
                all.iter()
                    .find(|t| t.id == id)
                    .cloned()
                    .ok_or_else(|| TargetError::UnknownId {
                        dataset: dataset.name(),
                        id,
                        valid: format!("1..={}", all.len()),
                    })
            })
            .collect::<Result<_, _>>()?,
    };
    if chosen.is_empty() {
        return Err(TargetError::NoTargets {
            dataset: dataset.name(),
        });
    }
    Ok(chosen)
}

fn eterna100(v2: bool) -> Result<Vec<Target>, TargetError> {
    let mut lines = ETERNA100_TSV.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split('\t').collect();
    let column = if v2 {
        "Secondary Structure V2"
    } else {
        "Secondary Structure V1"
    };
    let col = header
        .iter()
        .position(|h| *h == column)
        .ok_or_else(|| TargetError::BadStructure {
            origin: "eterna100_puzzles.tsv".into(),
            reason: format!("no column {column:?}"),
        })?;
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split('\t').collect();
            let id: u32 = fields[0].parse().map_err(|_| TargetError::BadStructure {
                origin: "eterna100_puzzles.tsv".into(),
                reason: format!("puzzle number {:?}", fields[0]),
            })?;
            Target::new(
                id,
                fields.get(col).copied().unwrap_or_default(),
                &format!("eterna100 puzzle {id}"),
            )
        })
        .collect()
}

/// The data directory: `explicit`, else `$CARL_SPEC_DATA`.
pub fn data_dir(explicit: Option<&Path>) -> Option<PathBuf> {
    explicit.map(Path::to_path_buf).or_else(|| {
        std::env::var_os(DATA_ENV_VAR)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    })
}

fn rfam_learn(
    split: RfamLearnSplit,
    ids: Option<&[u32]>,
    data_dir_opt: Option<&Path>,
) -> Result<Vec<Target>, TargetError> {
    let dir = data_dir(data_dir_opt)
        .unwrap_or_else(|| PathBuf::from(format!("${DATA_ENV_VAR}")))
        .join("rna")
        .join(format!("rfam_learn_{}", split.name()));
    if !dir.is_dir() {
        return Err(TargetError::RfamLearnMissing { path: dir });
    }
    let io = |path: &Path, e: std::io::Error| TargetError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let read = |id: u32| -> Result<Target, TargetError> {
        let path = dir.join(format!("{id}.rna"));
        let text = std::fs::read_to_string(&path).map_err(|e| io(&path, e))?;
        Target::new(id, &text, &path.display().to_string())
    };
    let dataset = Dataset::RfamLearn(split);
    let targets = match ids {
        Some(ids) => ids
            .iter()
            .map(|&id| {
                if dir.join(format!("{id}.rna")).is_file() {
                    read(id)
                } else {
                    Err(TargetError::UnknownId {
                        dataset: dataset.name(),
                        id,
                        valid: format!("the N.rna files in {}", dir.display()),
                    })
                }
            })
            .collect::<Result<Vec<_>, _>>()?,
        None => {
            let mut ids: Vec<u32> = std::fs::read_dir(&dir)
                .map_err(|e| io(&dir, e))?
                .filter_map(|entry| {
                    let name = entry.ok()?.file_name().into_string().ok()?;
                    name.strip_suffix(".rna")?.parse().ok()
                })
                .collect();
            ids.sort_unstable();
            ids.into_iter().map(read).collect::<Result<Vec<_>, _>>()?
        }
    };
    if targets.is_empty() {
        return Err(TargetError::NoTargets {
            dataset: dataset.name(),
        });
    }
    Ok(targets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_datasets_have_their_sizes_and_lengths() {
        let v1 = load(Dataset::Eterna, None, None).unwrap();
        assert_eq!(v1.len(), 100);
        assert_eq!(v1[0].structure, "(((((......)))))");
        assert_eq!(v1.iter().map(Target::len).max(), Some(400));
        let v2 = load(Dataset::EternaV2, None, None).unwrap();
        let redesigned = v1.iter().zip(&v2).filter(|(a, b)| a.structure != b.structure).count();
        assert_eq!(redesigned, 19);
        let taneda = load(Dataset::RfamTaneda, None, None).unwrap();
        assert_eq!(taneda.len(), 29);
        let lens: Vec<usize> = taneda.iter().map(Target::len).collect();
        assert_eq!((lens.iter().min(), lens.iter().max()), (Some(&54), Some(&451)));
    }

    #[test]
    fn ids_select_in_the_given_order_and_unknown_ids_are_errors() {
        let t = load(Dataset::RfamTaneda, Some(&[3, 1]), None).unwrap();
        assert_eq!(t.iter().map(|t| t.id).collect::<Vec<_>>(), [3, 1]);
        let err = load(Dataset::Eterna, Some(&[101]), None).unwrap_err();
        assert!(err.to_string().contains("no target with id 101"), "{err}");
    }

    #[test]
    fn rfam_learn_reads_learna_layout_and_explains_when_missing() {
        let root = std::env::temp_dir().join(format!("carl_rna_rfam_learn_{}", std::process::id()));
        let err = load(Dataset::RfamLearn(RfamLearnSplit::Test), None, Some(&root)).unwrap_err();
        assert!(matches!(err, TargetError::RfamLearnMissing { .. }));
        assert!(
            err.to_string().contains("CARL_SPEC_DATA") && err.to_string().contains("learna"),
            "{err}"
        );
        let dir = root.join("rna/rfam_learn_test");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("2.rna"), "((((....))))\n").unwrap();
        std::fs::write(dir.join("10.rna"), "((...))..\n").unwrap();
        std::fs::write(dir.join("notes.txt"), "ignored").unwrap();
        let all = load(Dataset::RfamLearn(RfamLearnSplit::Test), None, Some(&root)).unwrap();
        assert_eq!(
            all.iter().map(|t| (t.id, t.structure.as_str())).collect::<Vec<_>>(),
            [(2, "((((....))))"), (10, "((...))..")]
        );
        let one = load(Dataset::RfamLearn(RfamLearnSplit::Test), Some(&[10]), Some(&root)).unwrap();
        assert_eq!(one[0].partner[0], Some(6));
        assert!(load(Dataset::RfamLearn(RfamLearnSplit::Test), Some(&[3]), Some(&root)).is_err());
        std::fs::write(dir.join("3.rna"), "((..\n").unwrap();
        let bad = load(Dataset::RfamLearn(RfamLearnSplit::Test), Some(&[3]), Some(&root)).unwrap_err();
        assert!(bad.to_string().contains("unmatched '('"), "{bad}");
        std::fs::remove_dir_all(&root).unwrap();
    }
}
