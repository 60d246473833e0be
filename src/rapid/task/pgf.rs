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
    crate::input::refuse_unread_encoding(file, bytes, "UTF-8 or ISO-8859-1 (Latin-1)")?;
    let text = decode_lossless(bytes);
    let mut reader = Reader::from_str(&text);
    let mut out = Vec::new();
    // The text of the `<Module>` element being read: quick-xml gives its
    // text, CDATA and entity references as separate events.
    let mut module: Option<(usize, String)> = None;
    let mut saw_program = false;
    let located = |pos: usize, what: String| {
        // A Latin-1 file was widened to UTF-8: count characters back to
        // the file's own bytes.
        let pos = match std::str::from_utf8(bytes) {
            Ok(_) => pos,
            Err(_) => text.get(..pos).map_or(pos, |t| t.chars().count()),
        };
        Error::input(what).at(Location::from_offset(file, bytes, pos))
    };
    loop {
        let pos = reader.buffer_position() as usize;
        match reader.read_event() {
            Ok(Event::Start(e)) => match e.name().as_ref() {
                b"Program" => saw_program = true,
                b"Module" => module = Some((pos, String::new())),
                _ => {}
            },
            Ok(Event::End(e)) if e.name().as_ref() == b"Module" => {
                let (at, name) = module.take().unwrap_or_default();
                let name = name.trim();
                if name.is_empty() {
                    return Err(located(at, "an empty <Module> element".to_string()));
                }
                out.push(name.to_string());
            }
            Ok(Event::Text(t)) => {
                if let Some((_, name)) = module.as_mut() {
                    let piece = t
                        .decode()
                        .map_err(|e| located(pos, format!("not a program file: {e}")))?;
                    name.push_str(&piece);
                }
            }
            Ok(Event::CData(t)) => {
                if let Some((_, name)) = module.as_mut() {
                    name.push_str(&decode_lossless(&t));
                }
            }
            Ok(Event::GeneralRef(r)) => {
                if let Some((_, name)) = module.as_mut() {
                    let entity = format!("&{};", decode_lossless(&r));
                    let piece = quick_xml::escape::unescape(&entity)
                        .map_err(|e| located(pos, format!("not a program file: {e}")))?;
                    name.push_str(&piece);
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
    if out.is_empty() {
        // A program of no modules would read as an empty program whose
        // check passes: say so instead.
        return Err(located(
            0,
            "the program file lists no modules (no <Module> element)".to_string(),
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
    fn reads_cdata_and_entities_and_refuses_no_modules() {
        let pgf =
            b"<Program><Module><![CDATA[Main.mod]]></Module><Module>R&amp;D.mod</Module></Program>";
        let m = super::modules("p.pgf", pgf).unwrap();
        assert_eq!(m, ["Main.mod", "R&D.mod"]);
        for empty in [
            b"<Program></Program>".as_slice(),
            b"<?xml version=\"1.0\"?>\n<Program>\n</Program>\n",
            b"<Program><Module> </Module></Program>",
        ] {
            let e = super::modules("p.pgf", empty).unwrap_err();
            assert!(e.to_string().contains("p.pgf"), "{e}");
        }
    }

    #[test]
    fn refuses_what_is_not_a_program_file() {
        let e = super::modules("p.pgf", b"<Program><Module>a.mod</Modul></Program>").unwrap_err();
        assert!(e.to_string().contains("p.pgf"), "{e}");
        assert!(super::modules("p.pgf", b"MODULE x\nENDMODULE\n").is_err());
    }
}
