"""ML target motion analysis without observer maneuver (Grinenkov & Mashoshin 2024)."""

from tracker.mltma.batch import MLBatch
from tracker.mltma.course import course_from_relative_deg, relative_course_deg, wrap180
from tracker.mltma.params import MLParams
from tracker.mltma.smoothing import trimmed_mean
from tracker.mltma.tracker import MLTracker, track_measurements

__all__ = ["MLBatch", "MLParams", "MLTracker", "course_from_relative_deg", "relative_course_deg",
           "track_measurements", "trimmed_mean", "wrap180"]
