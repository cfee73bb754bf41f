"""The ground floor: errors, config loading, atomic files and training folders, event log, paths."""
