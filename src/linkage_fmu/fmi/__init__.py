"""FMI layers of the linkages: the guard in front of pythonfmu's wrapper."""
