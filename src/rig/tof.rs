//! A reader of Jolt Physics' text object stream (`TOS 1.00`), as far as the shipped ragdoll
//! and its animations need it.
//!
//! After the header `TOS 1.00` come blocks. `declare TypeName N` lists N `fieldName type`
//! pairs: a primitive (`uint8`, `uint16`, `uint32`, `float`, `bool`, `string`, `vec3`, `quat`,
//! `mat44`), `instance T`, `pointer T` or `array` then a type; a subclass lists its base class's
//! fields first. `object TypeName HEXID` gives the values in declared order: vectors as their
//! components (`quat` as `x y z w`, `mat44` column by column), an array as its count then its
//! elements, a string quoted with `\\`, `\"`, `\n`, `\t` escapes. `instance T` is either a member
//! held by value, whose fields follow inline, or one held by Jolt's reference-counted pointers
//! (`Ref<T>`), written as a hex id (`00000000` for null): Jolt tells them apart by the compiled
//! member, so [`REFERENCE_TYPES`] lists the classes it holds by reference. Ids may name objects
//! further down, but a type is declared before an object of it is read or inlined. Every error
//! names the file, the line and the object and field, and no input makes the reader panic.

use crate::math::{Quat, Vec3};
use std::{collections::HashMap, str::FromStr};

/// Classes Jolt holds by `Ref`/`RefConst`: an `instance` member of these types is an id.
pub const REFERENCE_TYPES: &[&str] = &[
    "ShapeSettings",
    "Skeleton",
    "ConstraintSettings",
    "TwoBodyConstraintSettings",
    "GroupFilter",
    "PhysicsMaterial",
    "RagdollSettings",
    "SkeletalAnimation",
];

/// Inline objects nest at most this deep, so a type that inlines itself is an error.
const MAX_DEPTH: usize = 32;

/// One whitespace-separated word or one quoted string (its escapes resolved), and its line.
#[derive(Clone, Debug, PartialEq)]
struct Token {
    text: String,
    quoted: bool,
    line: usize,
}

/// Jolt's `isspace`: space, tab, line feed, vertical tab, form feed, carriage return.
fn is_space(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\n' | '\r' | '\x0b' | '\x0c')
}

/// Splits `text` into tokens. A token starting with `"` runs to the next unescaped `"`; inside,
/// line feeds and tabs are dropped and `\\`, `\"`, `\n`, `\t` are escapes, as Jolt reads them.
fn tokenize(text: &str, file: &str) -> Result<Vec<Token>, String> {
    let (mut tokens, mut at, mut chars) = (Vec::new(), 1, text.chars().peekable());
    while let Some(c) = chars.next() {
        at += usize::from(c == '\n');
        if is_space(c) {
            continue;
        }
        let (mut text, quoted, line) = (String::new(), c == '"', at);
        if quoted {
            let mut escaped = false;
            loop {
                let Some(c) = chars.next() else {
                    return Err(format!("{file}:{line}: a string runs to the end of file"));
                };
                at += usize::from(c == '\n');
                match (c, escaped) {
                    ('\n' | '\t', _) => continue,
                    ('"', false) => break,
                    ('\\', false) => {}
                    (_, false) | ('\\' | '"', true) => text.push(c),
                    ('n', true) => text.push('\n'),
                    ('t', true) => text.push('\t'),
                    _ => {}
                }
                escaped = c == '\\' && !escaped;
            }
        } else {
            text.push(c);
            while let Some(c) = chars.next_if(|&c| !is_space(c)) {
                text.push(c);
            }
        }
        tokens.push(Token { text, quoted, line });
    }
    Ok(tokens)
}

/// A declared field type: `Uint` carries its largest value, `Instance` and `Pointer` their
/// class, `Array` its element type.
#[derive(Clone, Debug, PartialEq)]
enum FieldType {
    Uint(u32),
    Float,
    Bool,
    Str,
    Vec3,
    Quat,
    Mat44,
    Instance(String),
    Pointer(String),
    Array(Box<FieldType>),
}

/// A value read from the stream.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A `float`.
    Float(f32),
    /// A `uint8`, `uint16` or `uint32`.
    Uint(u32),
    /// A `bool`.
    Bool(bool),
    /// A `string`.
    Str(String),
    /// A `vec3`.
    Vec3(Vec3),
    /// A `quat`, as written (not normalized).
    Quat(Quat),
    /// A `mat44`, column by column.
    Mat44([f32; 16]),
    /// A reference to an object by id; 0 is null.
    Id(u32),
    /// An array's elements.
    Array(Vec<Value>),
    /// An inline instance.
    Object(Object),
}

/// A field's value and the line it starts on.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The member's name.
    pub name: String,
    /// 1-based line of the value's first token.
    pub line: usize,
    /// The value.
    pub value: Value,
}

/// An object: a top-level `object` block or an inline instance inside one.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The declared type's name.
    pub type_name: String,
    /// The id of a top-level object; `None` inline.
    pub id: Option<u32>,
    /// 1-based line where the object starts.
    pub line: usize,
    /// The enclosing top-level object, as `TypeName HEXID`.
    pub label: String,
    /// The field path from the top-level object (`mParts[3].mCollisionGroup`), or empty.
    pub path: String,
    /// Field values in declared order.
    pub fields: Vec<Field>,
}

/// What reading and typed access return: a value or an error naming file, line and field.
type R<T> = Result<T, String>;

/// `path.name`, or `name` at the top.
fn join(path: &str, name: &str) -> String {
    if path.is_empty() {
        name.to_string()
    } else {
        format!("{path}.{name}")
    }
}

/// A parsed file: its top-level objects in file order, indexed by id.
#[derive(Clone, Debug)]
pub struct Document {
    /// The file name errors name.
    pub file: String,
    /// Top-level objects in file order; the first is the file's main object.
    pub objects: Vec<Object>,
    ids: HashMap<u32, usize>,
}

/// The cursor over the tokens, the declared types (field name and type, in order), the file
/// name and the top-level object being read, which errors carry.
#[derive(Default)]
struct Reader<'a> {
    file: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    types: HashMap<String, Vec<(String, FieldType)>>,
    end_line: usize,
    label: String,
    /// Every reference read, with the `file:line: Type ID field path` its error names.
    ids: Vec<(u32, String)>,
}

impl Reader<'_> {
    /// `file:line: what: msg`.
    fn err(&self, line: usize, what: &str, msg: impl std::fmt::Display) -> String {
        format!("{}:{line}: {what}: {msg}", self.file)
    }

    /// The next token; at the end of the file an error naming `what` was expected.
    fn next(&mut self, what: &str) -> Result<Token, String> {
        self.pos += 1;
        let t = self.tokens.get(self.pos - 1).cloned();
        t.ok_or_else(|| self.err(self.end_line, what, "unexpected end of file"))
    }

    /// The line of the next token (the last line at the end of the file).
    fn line(&self) -> usize {
        self.tokens.get(self.pos).map_or(self.end_line, |t| t.line)
    }

    /// The next token parsed as a `T` that passes `ok` (quoted strings never do).
    fn parse<T: FromStr>(&mut self, what: &str, kind: &str, ok: impl Fn(&T) -> bool) -> R<T> {
        let t = self.next(what)?;
        match t.text.parse::<T>() {
            Ok(x) if !t.quoted && ok(&x) => Ok(x),
            _ => Err(self.err(t.line, what, format!("expected {kind}, got {:?}", t.text))),
        }
    }

    /// The next token as a hex object id (0 for null), kept to check that it exists.
    fn id(&mut self, what: &str) -> R<u32> {
        let t = self.next(what)?;
        match u32::from_str_radix(&t.text, 16) {
            Ok(id) if !t.quoted && !t.text.starts_with('+') => {
                self.ids.push((id, self.err(t.line, what, "")));
                Ok(id)
            }
            _ => Err(self.err(t.line, what, format!("expected a hex id, got {:?}", t.text))),
        }
    }

    fn declaration(&mut self) -> R<()> {
        let name = self.next("declare")?.text;
        let what = &format!("declare {name}");
        let left = self.tokens.len().saturating_sub(self.pos);
        let n = self.parse::<usize>(what, "a field count", |&n| n <= left)?;
        if self.types.contains_key(&name) {
            return Err(self.err(self.line(), what, "declared twice"));
        }
        let mut fields = Vec::with_capacity(n);
        for _ in 0..n {
            let field = self.next(what)?.text;
            let ty = self.field_type(&format!("{what} field {field}"), 0)?;
            fields.push((field, ty));
        }
        self.types.insert(name, fields);
        Ok(())
    }

    fn field_type(&mut self, what: &str, depth: usize) -> R<FieldType> {
        let t = self.next(what)?;
        Ok(match t.text.to_ascii_lowercase().as_str() {
            "array" if depth < MAX_DEPTH => {
                FieldType::Array(Box::new(self.field_type(what, depth + 1)?))
            }
            "uint8" => FieldType::Uint(u8::MAX.into()),
            "uint16" => FieldType::Uint(u16::MAX.into()),
            "uint32" => FieldType::Uint(u32::MAX),
            "float" => FieldType::Float,
            "bool" => FieldType::Bool,
            "string" => FieldType::Str,
            "vec3" => FieldType::Vec3,
            "quat" => FieldType::Quat,
            "mat44" => FieldType::Mat44,
            "instance" => FieldType::Instance(self.next(what)?.text),
            "pointer" => FieldType::Pointer(self.next(what)?.text),
            _ => return Err(self.err(t.line, what, format!("unknown type {:?}", t.text))),
        })
    }

    fn object(&mut self) -> R<Object> {
        let ty = self.next("object")?.text;
        let (what, line) = (&format!("object {ty}"), self.line());
        let id = self.id(what)?;
        self.label = format!("{ty} {id:08X}");
        if id == 0 || !self.types.contains_key(&ty) {
            return Err(self.err(line, what, "null id or undeclared type"));
        }
        let mut object = self.fields(&ty, "", line, 0)?;
        object.id = Some(id);
        Ok(object)
    }

    /// Reads the fields of an instance of the declared type `ty` that starts at `line`.
    fn fields(&mut self, ty: &str, path: &str, line: usize, depth: usize) -> R<Object> {
        let decls = self.types.get(ty).cloned().unwrap_or_default();
        let mut fields = Vec::with_capacity(decls.len());
        for (name, ty) in decls {
            let line = self.line();
            let value = self.value(&ty, &join(path, &name), depth)?;
            fields.push(Field { name, line, value });
        }
        let (label, path, type_name) = (self.label.clone(), path.to_string(), ty.to_string());
        Ok(Object {
            type_name,
            id: None,
            line,
            label,
            path,
            fields,
        })
    }

    fn value(&mut self, ty: &FieldType, path: &str, depth: usize) -> R<Value> {
        let what = &format!("{} field {path}", self.label);
        let mut float = || self.parse::<f32>(what, "a float", |x| x.is_finite());
        Ok(match ty {
            FieldType::Float => Value::Float(float()?),
            FieldType::Vec3 => Value::Vec3(Vec3::new(float()?, float()?, float()?)),
            FieldType::Quat => Value::Quat(Quat::from_xyzw(float()?, float()?, float()?, float()?)),
            FieldType::Mat44 => {
                let m = (0..16).map(|_| float()).collect::<R<Vec<f32>>>()?;
                Value::Mat44(m.try_into().unwrap_or_default())
            }
            FieldType::Uint(max) => Value::Uint(self.parse(what, "an integer", |x| x <= max)?),
            FieldType::Bool => Value::Bool(self.parse(what, "true or false", |_| true)?),
            FieldType::Str => match self.next(what)? {
                t if t.quoted => Value::Str(t.text),
                t => return Err(self.err(t.line, what, "expected a quoted string")),
            },
            FieldType::Instance(class) if !REFERENCE_TYPES.contains(&class.as_str()) => {
                let line = self.line();
                if !self.types.contains_key(class) || depth >= MAX_DEPTH {
                    let msg = format!("undeclared type {class} or nesting too deep");
                    return Err(self.err(line, what, msg));
                }
                Value::Object(self.fields(class, path, line, depth + 1)?)
            }
            FieldType::Instance(_) | FieldType::Pointer(_) => Value::Id(self.id(what)?),
            FieldType::Array(element) => {
                let left = self.tokens.len().saturating_sub(self.pos);
                let n = self.parse::<usize>(what, "an element count", |&n| n <= left)?;
                let mut items = Vec::with_capacity(n);
                for i in 0..n {
                    items.push(self.value(element, &format!("{path}[{i}]"), depth)?);
                }
                Value::Array(items)
            }
        })
    }
}

impl Document {
    /// Parses `text`; `file` is the name errors carry.
    pub fn parse(text: &str, file: &str) -> Result<Document, String> {
        let tokens = tokenize(text, file)?;
        let end_line = tokens.last().map_or(1, |t| t.line);
        let mut r = Reader {
            file,
            tokens,
            end_line,
            ..Reader::default()
        };
        let header = [r.next("header")?, r.next("header")?];
        if header[0].text != "TOS" || header[1].text != "1.00" {
            return Err(r.err(header[0].line, "header", "expected TOS 1.00"));
        }
        let (mut objects, mut index) = (Vec::<Object>::new(), HashMap::new());
        while r.pos < r.tokens.len() {
            let t = r.next("block")?;
            match t.text.to_ascii_lowercase().as_str() {
                "declare" => r.declaration()?,
                "object" => {
                    let o = r.object()?;
                    if index.insert(o.id.unwrap_or(0), objects.len()).is_some() {
                        return Err(r.err(t.line, &o.label, "id used twice"));
                    }
                    objects.push(o);
                }
                w => return Err(r.err(t.line, "block", format!("unexpected {w:?}"))),
            }
        }
        for (id, at) in &r.ids {
            if *id != 0 && !index.contains_key(id) {
                return Err(format!("{at}no object has the id {id:08X}"));
            }
        }
        let (file, ids) = (file.to_string(), index);
        Ok(Document { file, objects, ids })
    }

    /// The file's main (first) object.
    pub fn root(&self) -> Result<View<'_>, String> {
        let obj = self.objects.first();
        let obj = obj.ok_or_else(|| format!("{}:1: the file has no object", self.file))?;
        Ok(View { doc: self, obj })
    }

    /// The top-level object with id `id`.
    pub fn get(&self, id: u32) -> Option<View<'_>> {
        let obj = &self.objects[*self.ids.get(&id)?];
        Some(View { doc: self, obj })
    }
}

/// An object and its document: typed field access with errors naming file, line and field.
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    /// The document holding the object.
    pub doc: &'a Document,
    /// The object.
    pub obj: &'a Object,
}

/// Typed field getters, each an error when the field holds another kind of value.
macro_rules! getters {
    ($($(#[$d:meta])* $f:ident -> $t:ty, $v:ident($x:ident) => $o:expr, $k:literal;)*) => {
        $($(#[$d])*
        pub fn $f(&self, name: &str) -> Result<$t, String> {
            let f = self.field(name)?;
            match &f.value {
                Value::$v($x) => Ok($o),
                _ => Err(self.error_at(f.line, name, concat!("expected ", $k))),
            }
        })*
    };
}

impl<'a> View<'a> {
    /// An error about field `name` at `line`: `file:line: Type ID field path.name: msg`.
    pub fn error_at(&self, line: usize, name: &str, msg: &str) -> String {
        let (file, label, path) = (&self.doc.file, &self.obj.label, join(&self.obj.path, name));
        format!("{file}:{line}: {label} field {path}: {msg}")
    }

    /// An error about field `name` at that field's line (the object's if it has none).
    pub fn error(&self, name: &str, msg: &str) -> String {
        let line = self.field(name).map_or(self.obj.line, |f| f.line);
        self.error_at(line, name, msg)
    }

    /// Whether the type declares field `name`.
    pub fn has(&self, name: &str) -> bool {
        self.obj.fields.iter().any(|f| f.name == name)
    }

    /// Field `name`, or an error when the type does not declare it.
    pub fn field(&self, name: &str) -> Result<&'a Field, String> {
        let f = self.obj.fields.iter().find(|f| f.name == name);
        f.ok_or_else(|| self.error_at(self.obj.line, name, "missing from the declaration"))
    }

    getters! {
        /// A `float` field.
        float -> f32, Float(x) => *x, "a float";
        /// An unsigned integer field.
        uint -> u32, Uint(x) => *x, "an unsigned integer";
        /// A `bool` field.
        boolean -> bool, Bool(x) => *x, "true or false";
        /// A `string` field.
        string -> &'a str, Str(x) => x.as_str(), "a string";
        /// A `vec3` field.
        vec3 -> Vec3, Vec3(x) => *x, "a vec3";
        /// A `mat44` field, column by column.
        mat44 -> [f32; 16], Mat44(x) => *x, "a mat44";
        /// An inline instance field.
        inline_object -> &'a Object, Object(obj) => obj, "an inline instance";
        /// The elements of an array field.
        array -> &'a [Value], Array(x) => x.as_slice(), "an array";
        /// The id in a reference field (0 for null).
        id -> u32, Id(x) => *x, "an object id";
    }

    /// A `quat` field, normalized; an error unless its length is within 1% of one.
    pub fn quat(&self, name: &str) -> Result<Quat, String> {
        let f = self.field(name)?;
        match &f.value {
            Value::Quat(q) if (q.length() - 1.0).abs() < 0.01 => Ok(q.normalize()),
            _ => Err(self.error_at(f.line, name, "expected a unit quat")),
        }
    }

    /// An inline instance field.
    pub fn inline(&self, name: &str) -> Result<View<'a>, String> {
        let obj = self.inline_object(name)?;
        Ok(View { doc: self.doc, obj })
    }

    /// An array of inline instances.
    pub fn inlines(&self, name: &str) -> Result<Vec<View<'a>>, String> {
        let view = |v: &'a Value| match v {
            Value::Object(obj) => Ok(View { doc: self.doc, obj }),
            _ => Err(self.error(name, "expected an array of inline instances")),
        };
        self.array(name)?.iter().map(view).collect()
    }

    /// An array of unsigned integers.
    pub fn uints(&self, name: &str) -> Result<Vec<u32>, String> {
        let uint = |v: &Value| match v {
            Value::Uint(x) => Ok(*x),
            _ => Err(self.error(name, "expected an array of unsigned integers")),
        };
        self.array(name)?.iter().map(uint).collect()
    }

    /// A reference field resolved to its object; `None` for null (parsing checked that every
    /// other id names an object).
    pub fn reference(&self, name: &str) -> Result<Option<View<'a>>, String> {
        Ok(self.doc.get(self.id(name)?))
    }
}
