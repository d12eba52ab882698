//! Plots a person can look at (SVG, PNG) and self-contained HTML reports.
