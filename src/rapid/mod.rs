//! Reading RAPID programs losslessly and rewriting their targets in place.
