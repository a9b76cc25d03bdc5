-- | The printer: normalised ST whose parse is the same tree (up to
-- positions). Keywords in upper case, two spaces of indentation, ELSIF,
-- integer literals in the base they were written in, reals as an exact
-- decimal, and only the parentheses that the precedence of Table 4-14 and
-- left associativity need (MT-OP-16, MT-OP-17).
module Stref.Syntax.Pretty
  ( prettyModule
  , prettyExpr
  , prettyStmts
  , prettyLiteral
  , prettyOperand
  ) where

import Data.Char (intToDigit, toUpper)
import Data.Ratio (denominator, numerator)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Lazy as TL
import qualified Data.Text.Lazy.Builder as B
import Numeric (showIntAtBase)
import Stref.Syntax
import Stref.Types (typeName)

prettyModule :: Module a -> Text
prettyModule (Module globals functions prog) =
  T.intercalate "\n" (map (T.unlines . varBlock) globals ++ map (T.unlines . function) functions ++ [T.unlines (program prog)])

function :: Function a -> [Text]
function (Function _ n result blocks body) =
  ["FUNCTION " <> identText n <> " : " <> typeName result]
    ++ concatMap varBlock blocks
    ++ stmts 1 body
    ++ ["END_FUNCTION"]

program :: Program a -> [Text]
program (Program _ n blocks body) =
  ["PROGRAM " <> identText n]
    ++ concatMap varBlock blocks
    ++ stmts 1 body
    ++ ["END_PROGRAM"]

varBlock :: VarBlock a -> [Text]
varBlock (VarBlock _ sec constant decls) =
  [header <> (if constant then " CONSTANT" else "")]
    ++ map (indent 1 . varDecl) decls
    ++ ["END_VAR"]
  where
    header = case sec of
      SecVar -> "VAR"
      SecInput -> "VAR_INPUT"
      SecInOut -> "VAR_IN_OUT"
      SecOutput -> "VAR_OUTPUT"

varDecl :: VarDecl a -> Text
varDecl (VarDecl _ names at ty ini) =
  T.intercalate ", " (map (identText . snd) names)
    <> maybe "" ((" AT " <>) . prettyOperand . snd) at
    <> " : "
    <> typeSpec ty
    <> maybe "" ((" := " <>) . initializer) ini
    <> ";"

typeSpec :: TypeSpec a -> Text
typeSpec = \case
  TBasic t -> typeName t
  TArray lo hi t -> "ARRAY[" <> prettyExpr lo <> ".." <> prettyExpr hi <> "] OF " <> typeName t

initializer :: Initializer a -> Text
initializer = \case
  InitExpr e -> prettyExpr e
  InitList _ es -> "[" <> T.intercalate ", " (map prettyExpr es) <> "]"

-- | @%M0010@, @%M0006.6@, @%TM0010[15]@ (addresses padded to four digits,
-- as in the manual's examples).
prettyOperand :: OperandRef -> Text
prettyOperand (OperandRef letters address sub) =
  "%" <> letters <> pad address <> case sub of
    NoSub -> ""
    BitOf b -> "." <> tshow b
    Position p -> "[" <> tshow p <> "]"
  where
    pad n = let s = tshow n in T.replicate (4 - T.length s) "0" <> s

------------------------------------------------------------------------------
-- Statements

indent :: Int -> Text -> Text
indent n t = T.replicate (2 * n) " " <> t

-- | Statements at an indentation level, one line each (compound statements
-- on several lines).
prettyStmts :: [Stmt a] -> Text
prettyStmts = T.unlines . stmts 0

stmts :: Int -> [Stmt a] -> [Text]
stmts n = concatMap (stmt n)

stmt :: Int -> Stmt a -> [Text]
stmt n = \case
  Assign _ lv e -> [indent n (lvalue lv <> " := " <> prettyExpr e <> ";")]
  CallStmt _ f args -> [indent n (call f args <> ";")]
  If _ branches els ->
    concat
      [ [indent n (kw <> " " <> prettyExpr c <> " THEN")] ++ stmts (n + 1) body
      | (kw, (c, body)) <- zip ("IF" : repeat "ELSIF") branches
      ]
      ++ elsePart els
      ++ [indent n "END_IF;"]
  Case _ sel arms els ->
    [indent n ("CASE " <> prettyExpr sel <> " OF")]
      ++ concat
        [ indent (n + 1) (T.intercalate ", " (map caseLabel labels) <> " :") : stmts (n + 2) body
        | CaseArm _ labels body <- arms
        ]
      ++ elsePart els
      ++ [indent n "END_CASE;"]
  While _ c body -> [indent n ("WHILE " <> prettyExpr c <> " DO")] ++ stmts (n + 1) body ++ [indent n "END_WHILE;"]
  Repeat _ body c -> [indent n "REPEAT"] ++ stmts (n + 1) body ++ [indent n ("UNTIL " <> prettyExpr c <> " END_REPEAT;")]
  For _ (_, v) start end step body ->
    [ indent n $
        "FOR " <> identText v <> " := " <> prettyExpr start <> " TO " <> prettyExpr end
          <> maybe "" ((" BY " <>) . prettyExpr) step
          <> " DO"
    ]
      ++ stmts (n + 1) body
      ++ [indent n "END_FOR;"]
  Exit _ -> [indent n "EXIT;"]
  Return _ -> [indent n "RETURN;"]
  Empty _ -> [indent n ";"]
  where
    elsePart = maybe [] (\body -> indent n "ELSE" : stmts (n + 1) body)

caseLabel :: CaseLabel a -> Text
caseLabel = \case
  LabelValue v -> prettyExpr v
  LabelRange lo hi -> prettyExpr lo <> ".." <> prettyExpr hi

lvalue :: LValue a -> Text
lvalue = \case
  LVar _ v -> identText v
  LIndex _ v i -> identText v <> "[" <> prettyExpr i <> "]"

call :: Ident -> [Expr a] -> Text
call f args = identText f <> "(" <> T.intercalate ", " (map prettyExpr args) <> ")"

------------------------------------------------------------------------------
-- Expressions

-- | Binding strength (Table 4-14): higher binds tighter.
binLevel :: BinOp -> Int
binLevel = \case
  Or -> 1
  Xor -> 2
  And -> 3
  Eq -> 4
  Ne -> 4
  Lt -> 5
  Gt -> 5
  Le -> 5
  Ge -> 5
  Add -> 6
  Sub -> 6
  Mul -> 7
  Div -> 7
  Mod -> 7

unaryLevel, atomLevel :: Int
unaryLevel = 8
atomLevel = 9

prettyExpr :: Expr a -> Text
prettyExpr = TL.toStrict . B.toLazyText . go 0
  where
    -- go p e: print e where a level below p needs parentheses. A builder,
    -- not Text: appending to a long left operand must not copy it again at
    -- every level of a long chain (1 + 1 + ... + 1 stays linear).
    go :: Int -> Expr a -> B.Builder
    go p e = let (lvl, t) = render e in if lvl < p then "(" <> t <> ")" else t
    render :: Expr a -> (Int, B.Builder)
    render = \case
      ELit _ l -> (if negativeLiteral l then unaryLevel else atomLevel, B.fromText (prettyLiteral l))
      EVar _ v -> (atomLevel, B.fromText (identText v))
      EIndex _ v i -> (atomLevel, B.fromText (identText v) <> "[" <> go 0 i <> "]")
      ECall _ f args -> (atomLevel, B.fromText (call f args))
      EUnary _ Neg x -> (unaryLevel, "-" <> (if startsWithMinus x then " " else "") <> go unaryLevel x)
      EUnary _ Not x -> (unaryLevel, "NOT " <> go unaryLevel x)
      -- left associative: the right operand of the same level needs parentheses
      EBinary _ op l r ->
        let q = binLevel op
         in (q, go q l <> " " <> B.fromText (binOpSymbol op) <> " " <> go (q + 1) r)
    -- what 'go unaryLevel' prints with a leading '-': everything below the
    -- unary level is parenthesised
    startsWithMinus = \case
      ELit _ l -> negativeLiteral l
      EUnary _ Neg _ -> True
      _ -> False

negativeLiteral :: Literal -> Bool
negativeLiteral = \case
  LInt v _ -> v < 0
  LReal r -> r < 0
  LBool _ -> False

-- | Integers in their base (@16#AA@), reals as an exact decimal (every real
-- the parser reads has a finite decimal expansion), booleans as TRUE/FALSE.
prettyLiteral :: Literal -> Text
prettyLiteral = \case
  LBool b -> if b then "TRUE" else "FALSE"
  LInt v base
    | v < 0 -> "-" <> prettyLiteral (LInt (negate v) base)
    | base `elem` [2, 8, 16] -> tshow base <> "#" <> T.pack (map toUpper (showIntAtBase (toInteger base) intToDigit v ""))
    | otherwise -> tshow v
  LReal r
    | r < 0 -> "-" <> prettyLiteral (LReal (negate r))
    | otherwise -> exactDecimal r

exactDecimal :: Rational -> Text
exactDecimal r =
  let d = denominator r
      (twos, rest2) = factorOut 2 d
      (fives, rest) = factorOut 5 rest2
      k = max twos fives
   in if rest /= 1
        then approximate
        else
          let scaled = numerator r * (10 ^ k) `div` d
              digits = T.pack (show scaled)
              padded = T.replicate (k + 1 - T.length digits) "0" <> digits
              (intPart, fracPart) = T.splitAt (T.length padded - k) padded
           in intPart <> "." <> (if T.null fracPart then "0" else fracPart)
  where
    factorOut :: Integer -> Integer -> (Int, Integer)
    factorOut p n
      | n `mod` p == 0 = let (c, m) = factorOut p (n `div` p) in (c + 1, m)
      | otherwise = (0, n)
    -- not produced by the parser: 40 decimals are the closest we can write
    approximate =
      let scaled = numerator r * (10 ^ (40 :: Int)) `div` denominator r
          digits = T.pack (show scaled)
          padded = T.replicate (41 - T.length digits) "0" <> digits
          (intPart, fracPart) = T.splitAt (T.length padded - 40) padded
       in intPart <> "." <> fracPart

tshow :: Show x => x -> Text
tshow = T.pack . show
