"""ML target motion analysis without observer maneuver (Grinenkov & Mashoshin 2024)."""

from tracker.mltma.batch import (MLBatch, MLParams, MLTracker, course_from_relative_deg,
                                 relative_course_deg, track_measurements, trimmed_mean, wrap180)

__all__ = ["MLBatch", "MLParams", "MLTracker", "course_from_relative_deg", "relative_course_deg",
           "track_measurements", "trimmed_mean", "wrap180"]
