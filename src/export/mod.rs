//! Writing a stroke graph as SVG and JSON.
