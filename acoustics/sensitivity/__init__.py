"""Environmental sensitivity studies: an ensemble of perturbed areas through BELLHOP, and what it says.

``perturbspec`` (what is uncertain), ``perturb`` (drawing it into member areas), ``spec`` (what
determines a study), ``members`` (one member's K(r)), ``study`` (the ensemble on threads or a Dask
cluster, and its dataset), ``summaries``, ``files``, ``writeback`` (the measured K error into an
area file), ``plot`` and ``studyfile`` (a study's files from the command line's options, written all
or none).
"""

from acoustics.sensitivity.files import StudyFileError, open_study, write_study
from acoustics.sensitivity.members import MemberResult, compute_member
from acoustics.sensitivity.perturbspec import PerturbationError, parse_spec
from acoustics.sensitivity.spec import RECIPROCITY_MIN_DEPTH_M, StudySpec
from acoustics.sensitivity.study import StudyStats, run_study
from acoustics.sensitivity.studyfile import output_files, run_study_file
from acoustics.sensitivity.summaries import DEFAULT_EVAL_RANGES_M, k_error_by_class, level_range_m, summarize
from acoustics.sensitivity.writeback import write_k_error

__all__ = ["DEFAULT_EVAL_RANGES_M", "MemberResult", "PerturbationError", "parse_spec", "RECIPROCITY_MIN_DEPTH_M",
           "StudyFileError", "StudySpec", "StudyStats", "compute_member", "k_error_by_class",
           "level_range_m", "open_study", "output_files", "run_study", "run_study_file", "summarize",
           "write_k_error", "write_study"]
