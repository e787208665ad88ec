//! The explicitly laid-out structs of a SPIR-V module (push-constant blocks, buffer-reference
//! blocks and the structs inside them), read from the debug names and `Offset` decorations
//! that build.rs keeps (`set_generate_debug_info`). Only what the layout check needs: the
//! types, names and decorations; instructions of any other kind are skipped by their length.

use std::collections::HashMap;

const MAGIC: u32 = 0x0723_0203;
const OP_NAME: u32 = 5;
const OP_MEMBER_NAME: u32 = 6;
const OP_TYPE_BOOL: u32 = 20;
const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_TYPE_MATRIX: u32 = 24;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_CONSTANT: u32 = 43;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_ARRAY_STRIDE: u32 = 6;
const DECORATION_MATRIX_STRIDE: u32 = 7;
const DECORATION_OFFSET: u32 = 35;
const STORAGE_PHYSICAL_STORAGE_BUFFER: u32 = 5349;

/// A scalar as both sides store it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scalar {
    F32,
    U32,
    I32,
    /// A 64-bit unsigned integer, or a buffer reference (a device address).
    U64,
}

impl Scalar {
    pub fn bytes(self) -> u32 {
        match self {
            Self::U64 => 8,
            _ => 4,
        }
    }
}

/// A SPIR-V type, as far as a layout goes.
#[derive(Debug, Clone)]
enum Type {
    Scalar(Scalar),
    /// A scalar neither side may share (bool, other widths): its opcode and width.
    Unshareable(&'static str),
    Vector(u32, u32),
    Matrix(u32, u32),
    Array {
        element: u32,
        length: u32,
    },
    RuntimeArray,
    Struct(Vec<u32>),
}

/// One scalar of a struct flattened: where it lies, what it is, and the name of the struct
/// member it belongs to (an array's or vector's elements all carry their member's name).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Leaf {
    pub offset: u32,
    pub scalar: Scalar,
    pub name: String,
}

/// The parsed module.
pub struct Module {
    names: HashMap<u32, String>,
    member_names: HashMap<(u32, u32), String>,
    offsets: HashMap<(u32, u32), u32>,
    matrix_strides: HashMap<(u32, u32), u32>,
    array_strides: HashMap<u32, u32>,
    constants: HashMap<u32, u32>,
    types: HashMap<u32, Type>,
}

fn string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

impl Module {
    /// Parses `bytes`, a little-endian SPIR-V module; the error says what is wrong.
    pub fn parse(bytes: &[u8]) -> Result<Self, String> {
        if bytes.len() % 4 != 0 || bytes.len() < 20 {
            return Err(format!("{} bytes is not a SPIR-V module", bytes.len()));
        }
        let words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if words[0] != MAGIC {
            return Err(format!("magic {:#x}, not SPIR-V's", words[0]));
        }
        let mut module = Self {
            names: HashMap::new(),
            member_names: HashMap::new(),
            offsets: HashMap::new(),
            matrix_strides: HashMap::new(),
            array_strides: HashMap::new(),
            constants: HashMap::new(),
            types: HashMap::new(),
        };
        let mut at = 5;
        while at < words.len() {
            let count = (words[at] >> 16) as usize;
            if count == 0 || at + count > words.len() {
                return Err(format!("instruction at word {at} has length {count}"));
            }
            module.read(words[at] & 0xffff, &words[at + 1..at + count]);
            at += count;
        }
        Ok(module)
    }

    fn read(&mut self, opcode: u32, op: &[u32]) {
        let ty = match opcode {
            OP_NAME => {
                self.names.insert(op[0], string(&op[1..]));
                return;
            }
            OP_MEMBER_NAME => {
                self.member_names.insert((op[0], op[1]), string(&op[2..]));
                return;
            }
            OP_DECORATE if op[1] == DECORATION_ARRAY_STRIDE => {
                self.array_strides.insert(op[0], op[2]);
                return;
            }
            OP_MEMBER_DECORATE if op[2] == DECORATION_OFFSET => {
                self.offsets.insert((op[0], op[1]), op[3]);
                return;
            }
            OP_MEMBER_DECORATE if op[2] == DECORATION_MATRIX_STRIDE => {
                self.matrix_strides.insert((op[0], op[1]), op[3]);
                return;
            }
            OP_CONSTANT => {
                self.constants.insert(op[1], op[2]);
                return;
            }
            OP_TYPE_BOOL => Type::Unshareable("bool"),
            OP_TYPE_INT => match (op[1], op[2]) {
                (32, 0) => Type::Scalar(Scalar::U32),
                (32, _) => Type::Scalar(Scalar::I32),
                (64, 0) => Type::Scalar(Scalar::U64),
                _ => Type::Unshareable("an integer of another width or signedness"),
            },
            OP_TYPE_FLOAT => match op[1] {
                32 => Type::Scalar(Scalar::F32),
                _ => Type::Unshareable("a float of another width"),
            },
            OP_TYPE_VECTOR => Type::Vector(op[1], op[2]),
            OP_TYPE_MATRIX => Type::Matrix(op[1], op[2]),
            OP_TYPE_ARRAY => Type::Array {
                element: op[1],
                length: op[2],
            },
            OP_TYPE_RUNTIME_ARRAY => Type::RuntimeArray,
            OP_TYPE_STRUCT => Type::Struct(op[1..].to_vec()),
            // A buffer reference: a device address, 8 bytes.
            OP_TYPE_POINTER if op[1] == STORAGE_PHYSICAL_STORAGE_BUFFER => {
                Type::Scalar(Scalar::U64)
            }
            _ => return,
        };
        self.types.insert(op[0], ty);
    }

    /// Every struct type named `name` whose members all have offsets (the explicitly laid-out
    /// copies; glslang also emits copies without offsets for values in private memory).
    pub fn laid_out_structs(&self, name: &str) -> Vec<u32> {
        let mut ids: Vec<u32> = self
            .types
            .iter()
            .filter(|(id, _)| self.names.get(id).is_some_and(|n| n == name))
            .filter_map(|(&id, ty)| match ty {
                Type::Struct(members) => (0..members.len() as u32)
                    .all(|m| self.offsets.contains_key(&(id, m)))
                    .then_some(id),
                _ => None,
            })
            .collect();
        ids.sort();
        ids
    }

    /// The struct `id` flattened into scalars, by offset; and its size rounded up to its
    /// alignment (std430: what a Rust `repr(C)` mirror's size must be).
    pub fn flatten(&self, id: u32) -> Result<(Vec<Leaf>, u32), String> {
        let mut leaves = Vec::new();
        let (size, align) = self.flatten_struct(id, 0, &mut leaves)?;
        leaves.sort_by_key(|l| l.offset);
        Ok((leaves, size.div_ceil(align) * align))
    }

    /// Appends the struct's scalars at `base`; returns its size (to the end of its last
    /// member) and alignment.
    fn flatten_struct(
        &self,
        id: u32,
        base: u32,
        out: &mut Vec<Leaf>,
    ) -> Result<(u32, u32), String> {
        let Some(Type::Struct(members)) = self.types.get(&id) else {
            return Err(format!("type {id} is not a struct"));
        };
        let (mut end, mut align) = (0, 1);
        for (m, &member) in members.iter().enumerate() {
            let key = (id, m as u32);
            let offset = *self
                .offsets
                .get(&key)
                .ok_or_else(|| format!("member {m} of struct {id} has no offset"))?;
            let name = self
                .member_names
                .get(&key)
                .cloned()
                .unwrap_or(format!("#{m}"));
            let stride = self.matrix_strides.get(&key).copied();
            let (size, a) = self.flatten_type(member, base + offset, &name, stride, out)?;
            end = end.max(offset + size);
            align = align.max(a);
        }
        Ok((end, align))
    }

    /// Appends the scalars of a value of type `id` at `at`; returns its size and alignment.
    fn flatten_type(
        &self,
        id: u32,
        at: u32,
        name: &str,
        matrix_stride: Option<u32>,
        out: &mut Vec<Leaf>,
    ) -> Result<(u32, u32), String> {
        let ty = self
            .types
            .get(&id)
            .ok_or(format!("`{name}`: unknown type {id}"))?;
        match ty {
            Type::Scalar(s) => {
                out.push(Leaf {
                    offset: at,
                    scalar: *s,
                    name: name.to_owned(),
                });
                Ok((s.bytes(), s.bytes()))
            }
            Type::Unshareable(what) => Err(format!("`{name}` is {what}: no Rust mirror")),
            Type::Vector(component, n) => {
                let Some(Type::Scalar(s)) = self.types.get(component) else {
                    return Err(format!("`{name}`: a vector of a type no mirror has"));
                };
                let size = s.bytes();
                for i in 0..*n {
                    self.flatten_type(*component, at + i * size, name, None, out)?;
                }
                // std430: a 3-component vector aligns as a 4-component one.
                let align = if *n == 2 { 2 * size } else { 4 * size };
                Ok((n * size, align))
            }
            Type::Matrix(column, n) => {
                let stride = matrix_stride.ok_or(format!("`{name}`: matrix without stride"))?;
                let mut align = 1;
                for i in 0..*n {
                    align = self
                        .flatten_type(*column, at + i * stride, name, None, out)?
                        .1;
                }
                Ok((n * stride, align))
            }
            Type::Array { element, length } => {
                let stride = *self
                    .array_strides
                    .get(&id)
                    .ok_or(format!("`{name}`: array without stride"))?;
                let length = *self
                    .constants
                    .get(length)
                    .ok_or(format!("`{name}`: array length is not a constant"))?;
                let mut align = 1;
                for i in 0..length {
                    align = self
                        .flatten_type(*element, at + i * stride, name, None, out)?
                        .1;
                }
                Ok((length * stride, align))
            }
            Type::RuntimeArray => Err(format!("`{name}` is a runtime array: no Rust mirror")),
            Type::Struct(_) => self.flatten_struct(id, at, out),
        }
    }
}
