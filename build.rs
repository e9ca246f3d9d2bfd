// Placeholder: the FMU issue makes this read and check modelDescription/ and
// generate the variable table.
fn main() {}
