//! Statistical comparison of images.
