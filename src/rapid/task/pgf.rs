//! Program files (`.pgf`): the XML list of a program's modules that
//! RobotStudio and the FlexPendant save beside them.
//!
//! ```xml
//! <?xml version="1.0" encoding="ISO-8859-1" ?>
//! <Program>
//!     <Module>MainModule.mod</Module>
//! </Program>
//! ```

use crate::error::{decode_lossless, Error, Location, Result};
use quick_xml::events::Event;
use quick_xml::Reader;

/// The module file names a program file lists, in its order (relative to
/// the program file's folder, as written).
pub fn modules(file: &str, bytes: &[u8]) -> Result<Vec<String>> {
    // ISO-8859-1 is what the controller writes; decoding byte for byte
    // keeps every offset of the file, for messages.
    let text = decode_lossless(bytes);
    let mut reader = Reader::from_str(&text);
    let mut out = Vec::new();
    let mut depth_module = false;
    let mut saw_program = false;
    let located = |pos: usize, what: String| {
        // A Latin-1 file was widened to UTF-8: count characters back to
        // the file's own bytes.
        let pos = match std::str::from_utf8(bytes) {
            Ok(_) => pos,
            Err(_) => text.get(..pos).map_or(pos, |t| t.chars().count()),
        };
        Error::input(format!("{file}: {what}")).at(Location::from_offset(file, bytes, pos))
    };
    loop {
        let pos = reader.buffer_position() as usize;
        match reader.read_event() {
            Ok(Event::Start(e)) => match e.name().as_ref() {
                b"Program" => saw_program = true,
                b"Module" => depth_module = true,
                _ => {}
            },
            Ok(Event::End(e)) if e.name().as_ref() == b"Module" => depth_module = false,
            Ok(Event::Text(t)) if depth_module => {
                let name = t
                    .decode()
                    .map_err(|e| located(pos, format!("not a program file: {e}")))?;
                let name = name.trim();
                if !name.is_empty() {
                    out.push(name.to_string());
                }
            }
            Ok(Event::Eof) => break,
            Ok(_) => {}
            Err(e) => {
                return Err(located(
                    reader.error_position() as usize,
                    format!("not a program file: {e}"),
                ))
            }
        }
    }
    if !saw_program {
        return Err(located(
            0,
            "not a program file: no <Program> element".to_string(),
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    #[test]
    fn lists_the_modules_in_order() {
        let pgf = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\" ?>\r\n<Program>\r\n  <Module>Main.mod</Module>\r\n  <Module> Fl\xe4che.mod </Module>\r\n</Program>\r\n";
        let m = super::modules("p.pgf", pgf).unwrap();
        assert_eq!(m, ["Main.mod", "Fl\u{e4}che.mod"]);
    }

    #[test]
    fn refuses_what_is_not_a_program_file() {
        let e = super::modules("p.pgf", b"<Program><Module>a.mod</Modul></Program>").unwrap_err();
        assert!(e.to_string().contains("p.pgf"), "{e}");
        assert!(super::modules("p.pgf", b"MODULE x\nENDMODULE\n").is_err());
    }
}
