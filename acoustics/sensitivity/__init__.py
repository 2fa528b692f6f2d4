"""Environmental sensitivity studies: an ensemble of perturbed areas through BELLHOP, and what it says.

``perturbspec`` (what is uncertain), ``perturb`` (drawing it into member areas), ``spec`` (what
determines a study), ``members`` (one member's K(r)), ``study`` (the ensemble on threads or a Dask
cluster, and its dataset), ``face`` (what a study's readers ask, ``Study``), ``summaries``,
``files`` (study files, opened as the face), ``writeback`` (the measured K error into an
area file), ``plot`` and ``studyfile`` (a study's files from the command line's options, written all
or none).
"""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "acoustics.sensitivity.face": ["Study", "StudyFileError", "study_face"],
    "acoustics.sensitivity.files": ["open_study", "write_study"],
    "acoustics.sensitivity.members": ["MemberResult", "compute_member"],
    "acoustics.sensitivity.perturbspec": ["PerturbationError", "parse_spec"],
    "acoustics.sensitivity.spec": ["RECIPROCITY_MIN_DEPTH_M", "StudySpec"],
    "acoustics.sensitivity.study": ["StudyStats", "run_study"],
    "acoustics.sensitivity.studyfile": ["output_files", "run_study_file"],
    "acoustics.sensitivity.summaries": [
        "DEFAULT_EVAL_RANGES_M", "k_error_by_class", "level_range_m", "summarize",
    ],
    "acoustics.sensitivity.writeback": ["write_k_error"],
})
