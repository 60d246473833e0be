//! The pest grammar of RAPID (`grammar/rapid.pest`): the authority on
//! what a program may say.

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/rapid.pest"]
pub(super) struct RapidParser;

/// `text` read by the grammar as `rule`.
pub(super) fn read(
    rule: Rule,
    text: &str,
) -> Result<pest::iterators::Pairs<'_, Rule>, Box<pest::error::Error<Rule>>> {
    <RapidParser as pest::Parser<Rule>>::parse(rule, text).map_err(Box::new)
}
