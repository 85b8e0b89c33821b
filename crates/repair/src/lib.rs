//! Format-agnostic trajectory repair: gaps, fills, spikes, filters, evaluation (see issue 3).
